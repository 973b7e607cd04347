// SPDX-License-Identifier: MIT
// A handshake mismatch stops both sides, each with a message naming the field and both values.
#include <gtest/gtest.h>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

struct Mismatch {
  const char* field;
  std::function<void(MembraneConfig&)> mutate;
  std::string expected;  ///< must appear in the fluid's and the membrane's message
};

/// Runs fluid (2 cells of 1002 nodes, node counts checked) against one mutated membrane.
std::pair<std::string, std::string> handshake_errors(const Mismatch& c) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid(
      {test_scene(2), fluid_endpoints(Kind::inproc, 1, dir), {1002, 1002}, test_options()},
      context);
  MembraneConfig mc{test_scene(2), fluid.endpoints()[0], "membrane-0", 0, 1, 0,
                    {1002, 1002},  test_options()};
  c.mutate(mc);
  std::string membrane_error = "(no error)";
  std::thread membrane_thread([&] {
    MembraneSide m(mc, context);
    try {
      m.initialize();
    } catch (const CouplerError& e) {
      membrane_error = e.what();
      EXPECT_EQ(m.state(), State::failed);
    }
  });
  std::string fluid_error = "(no error)";
  try {
    fluid.initialize();
  } catch (const CouplerError& e) {
    fluid_error = e.what();
    EXPECT_EQ(fluid.state(), State::failed);
  }
  membrane_thread.join();
  return {fluid_error, membrane_error};
}

class HandshakeMismatch : public ::testing::TestWithParam<Mismatch> {};

TEST_P(HandshakeMismatch, StopsBothSidesNamingTheField) {
  const auto [fluid_error, membrane_error] = handshake_errors(GetParam());
  EXPECT_TRUE(fluid_error.starts_with("fluid: handshake: field '")) << fluid_error;
  EXPECT_NE(fluid_error.find(GetParam().expected), std::string::npos) << fluid_error;
  EXPECT_NE(membrane_error.find("membrane 'membrane-0': fluid reported an error at step 0: "),
            std::string::npos)
      << membrane_error;
  EXPECT_NE(membrane_error.find(GetParam().expected), std::string::npos) << membrane_error;
}

const std::string kM = "membrane 'membrane-0'";

INSTANTIATE_TEST_SUITE_P(
    EveryField, HandshakeMismatch,
    ::testing::Values(
        Mismatch{"scene_hash", [](auto& m) { m.scene.scene_hash = "sha256:other"; },
                 "handshake: field 'scene_hash': fluid has 'sha256:0123456789abcdef', " + kM +
                     " has 'sha256:other'"},
        Mismatch{"dx_m", [](auto& m) { set_value(m.scene, "dx_m", 0.5e-6); },
                 "field 'dx_m': fluid has 4e-07, " + kM + " has 5e-07"},
        Mismatch{"dt_s", [](auto& m) { set_value(m.scene, "dt_s", 2.2e-8); },
                 "handshake: field 'dt_s': fluid has 2.1e-08, " + kM + " has 2.2e-08"},
        Mismatch{"density_kg_m3", [](auto& m) { set_value(m.scene, "density_kg_m3", 1000); },
                 "field 'density_kg_m3': fluid has 1025, " + kM + " has 1000"},
        Mismatch{"lambda_m", [](auto& m) { set_value(m.scene, "lambda_m", 30e-6); },
                 "field 'lambda_m': fluid has 3.2e-05, " + kM + " has 3e-05"},
        Mismatch{"radius_m", [](auto& m) { set_value(m.scene, "radius_m", 7e-6); },
                 "field 'radius_m': fluid has 8e-06, " + kM + " has 7e-06"},
        Mismatch{"depth_m", [](auto& m) { set_value(m.scene, "depth_m", 4e-6); },
                 "field 'depth_m': fluid has 4.4e-06, " + kM + " has 4e-06"},
        Mismatch{"shift_m", [](auto& m) { set_value(m.scene, "shift_m", 3e-6); },
                 "field 'shift_m': fluid has 3.2e-06, " + kM + " has 3e-06"},
        Mismatch{"value_only_the_fluid_has", [](auto& m) { m.scene.agreed.pop_back(); },
                 "field 'shift_m': fluid has 3.2e-06, " + kM + " has none"},
        Mismatch{"value_only_the_membrane_has",
                 [](auto& m) {
                   m.scene.agreed.push_back({"viscosity_ratio", 5.0, 0.0});
                 },
                 "field 'viscosity_ratio': fluid has none, " + kM + " has 5"},
        Mismatch{"within_the_tolerance_agrees_beyond_it_does_not",
                 [](auto& m) {
                   m.scene.agreed[0].value *= 1 + 1e-13;  // dx_m: within 1e-12, so agreed
                   m.scene.agreed[1].tolerance = 0.01;    // dt_s: the wider of the two counts
                   m.scene.agreed[1].value *= 1.005;
                   m.scene.agreed[2].value *= 1.5;
                 },
                 "field 'density_kg_m3': fluid has 1025, " + kM + " has 1537.5"},
        Mismatch{"start_step", [](auto& m) { m.scene.start_step = 5; },
                 "field 'start_step': fluid has 0, " + kM + " has 5"},
        Mismatch{"total_cells", [](auto& m) { m.scene.total_cells = 3; },
                 "field 'total_cells': fluid has 2, " + kM + " has 3"},
        Mismatch{"peer_count", [](auto& m) { m.peer_count = 2; },
                 "field 'peer_count': fluid has 1, " + kM + " has 2"},
        Mismatch{"peer_index", [](auto& m) { m.peer_index = 1; },
                 "field 'peer_index': fluid has 0, " + kM + " has 1"},
        Mismatch{"first_cell", [](auto& m) { m.first_cell = 1; },
                 "field 'first_cell': fluid has 0, " + kM + " has 1"},
        Mismatch{"cell_nodes",
                 [](auto& m) {
                   m.cell_nodes = {1002, 1001};
                 },
                 "field 'cell_nodes[1]': fluid has 1002, " + kM + " has 1001"},
        Mismatch{"owned_cells", [](auto& m) { m.cell_nodes = {1002}; },
                 "field 'total_cells': fluid expects 2 cells, the 1 membrane peer(s) own 1"}),
    [](const auto& p) { return std::string(p.param.field); });

TEST(Handshake, ProtocolVersionMismatchIsNamed) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
                  context);
  RawPeer raw(context, fluid.endpoints()[0], false);
  zmq::message_t hello = encode_handshake(FrameType::hello, hello_for(test_scene(1), {10}));
  static_cast<std::uint8_t*>(hello.data())[4] = 5;  // a membrane speaking protocol version 5
  raw.send(std::move(hello));
  try {
    fluid.initialize();
    FAIL() << "no error";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid: handshake: field 'protocol_version': fluid has 4, membrane peer 0 has 5");
  }
  auto reply = raw.receive();
  ASSERT_TRUE(reply);
  EXPECT_EQ(RawPeer::type_of(*reply), FrameType::error);
}

TEST(Handshake, MembraneChecksTheWelcomeToo) {
  zmq::context_t context;
  TempDir dir;
  RawPeer raw_fluid(context, "inproc://welcome-check", true);
  MembraneSide m({test_scene(1), raw_fluid.endpoint(), "membrane-0", 0, 1, 0, {10}, test_options()},
                 context);
  Handshake welcome = hello_for(test_scene(1), {10}, "fluid");
  set_value(welcome.scene, "dt_s", 2.5e-8);
  raw_fluid.send(encode_handshake(FrameType::welcome, welcome));
  try {
    m.initialize();
    FAIL() << "no error";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "membrane 'membrane-0': handshake: field 'dt_s': fluid has 2.5e-08, membrane "
              "'membrane-0' has 2.1e-08");
  }
  auto hello = raw_fluid.receive();
  ASSERT_TRUE(hello);
  EXPECT_EQ(RawPeer::type_of(*hello), FrameType::hello);
  auto error = raw_fluid.receive();
  ASSERT_TRUE(error);
  EXPECT_EQ(RawPeer::type_of(*error), FrameType::error);
}

TEST(Handshake, MismatchOfOnePeerStopsEveryPeer) {
  const std::vector<std::vector<std::uint32_t>> split{{100}, {100}};
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(2), fluid_endpoints(Kind::inproc, 2, dir), {}, test_options()},
                  context);
  std::string errors[2];
  std::vector<std::thread> threads;
  for (std::uint32_t k = 0; k < 2; ++k) {
    threads.emplace_back([&, k] {
      MembraneConfig mc{
          test_scene(2), fluid.endpoints()[k], "membrane-" + std::to_string(k), k, 2, k,
          {100},         test_options()};
      if (k == 1) mc.scene.scene_hash = "sha256:stale";
      MembraneSide m(mc, context);
      try {
        m.initialize();
      } catch (const CouplerError& e) {
        errors[k] = e.what();
      }
    });
  }
  EXPECT_THROW(fluid.initialize(), CouplerError);
  for (auto& t : threads) t.join();
  for (const auto& e : errors) {
    EXPECT_NE(e.find("field 'scene_hash'"), std::string::npos) << e;
    EXPECT_NE(e.find("membrane 'membrane-1' has 'sha256:stale'"), std::string::npos) << e;
  }
}

// The fluid gathers the cell surfaces of every peer in global cell order (protocol v2); a peer
// without surfaces (a tracer program) reads as cells with zero triangles.
TEST(Handshake, FluidGathersTheSurfacesOfEveryPeer) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(3), fluid_endpoints(Kind::inproc, 2, dir), {}, test_options()},
                  context);
  const std::vector<std::uint32_t> tetra{0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0};
  std::vector<std::thread> threads;
  for (std::uint32_t k = 0; k < 2; ++k) {
    threads.emplace_back([&, k] {
      const std::vector<std::uint32_t> cells =
          k == 0 ? std::vector<std::uint32_t>{4, 5} : std::vector<std::uint32_t>{7};
      MembraneSide m({test_scene(3), fluid.endpoints()[k], "membrane-" + std::to_string(k), k, 2,
                      k == 0 ? 0u : 2u, cells, test_options()},
                     context);
      if (k == 0) {
        std::vector<std::uint32_t> faces = tetra;
        for (std::uint32_t v : tetra) faces.push_back(v == 3 ? 4 : v);  // cell 1: apex is node 4
        m.set_cell_surfaces({4, 4}, faces);
      }
      m.initialize();
      m.finalize();
    });
  }
  fluid.initialize();
  EXPECT_EQ(std::vector<std::uint32_t>(fluid.cell_faces().begin(), fluid.cell_faces().end()),
            (std::vector<std::uint32_t>{4, 4, 0}));
  ASSERT_EQ(fluid.faces().size(), 24u);
  EXPECT_EQ(fluid.faces()[16], 4u);  // second cell's second triangle: 0, 4, 1
  while (fluid.receive()) {
  }
  fluid.finalize();
  for (auto& t : threads) t.join();
}

}  // namespace
}  // namespace dld::coupler::test
