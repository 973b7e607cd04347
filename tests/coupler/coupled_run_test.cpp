// SPDX-License-Identifier: MIT
// Coupled runs with both sides as threads: data arrives bit-exact over every transport, the
// three transports give identical runs, and K membrane peers are concatenated in peer order.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <functional>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

bool bit_equal(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

/// Checks what the fluid received against what the membranes sent, and what the membranes
/// received against the dummy fluid's answer, bit for bit.
void expect_exact(const RunRecord& rec, const std::vector<std::vector<std::uint32_t>>& split,
                  int steps) {
  ASSERT_EQ(rec.fluid_error, "");
  for (const auto& e : rec.membrane_errors) ASSERT_EQ(e, "");
  ASSERT_EQ(rec.fluid_positions.size(), static_cast<std::size_t>(steps));
  std::size_t first_node = 0;
  for (std::size_t k = 0; k < split.size(); ++k) {
    const std::size_t nodes = std::accumulate(split[k].begin(), split[k].end(), std::size_t{0});
    ASSERT_EQ(rec.membrane_velocities[k].size(), static_cast<std::size_t>(steps));
    for (int s = 0; s < steps; ++s) {
      std::vector<double> x(3 * nodes), f(3 * nodes), u;
      fill_nodes(s, first_node, x, f);
      const auto slice = [&](const std::vector<double>& all) {
        return std::vector<double>(all.begin() + 3 * first_node,
                                   all.begin() + 3 * (first_node + nodes));
      };
      EXPECT_TRUE(bit_equal(slice(rec.fluid_positions[s]), x)) << "peer " << k << " step " << s;
      EXPECT_TRUE(bit_equal(slice(rec.fluid_forces[s]), f)) << "peer " << k << " step " << s;
      dummy_velocities(s, x, f, u);
      EXPECT_TRUE(bit_equal(rec.membrane_velocities[k][s], u)) << "peer " << k << " step " << s;
    }
    first_node += nodes;
  }
}

class CoupledRun : public ::testing::TestWithParam<Kind> {};

TEST_P(CoupledRun, DataArrivesBitExact) {
  const std::vector<std::vector<std::uint32_t>> split{{1002, 642, 1002}};
  const RunRecord rec = run_coupled(GetParam(), split, 5);
  expect_exact(rec, split, 5);
}

TEST_P(CoupledRun, TwoMembranePeersAreConcatenatedInPeerOrder) {
  const std::vector<std::vector<std::uint32_t>> split{{1002, 642}, {12, 1002, 7}};
  const RunRecord rec = run_coupled(GetParam(), split, 4);
  expect_exact(rec, split, 4);
}

TEST_P(CoupledRun, SharedMemoryOnlyOnIpc) {
  const RunRecord rec = run_coupled(GetParam(), {{10}, {20}}, 2);
  expect_exact(rec, {{10}, {20}}, 2);
  for (int shared : rec.shared_memory) EXPECT_EQ(shared != 0, GetParam() == Kind::ipc);
}

// The zero-copy way: both sides write into the coupler's buffers (the shared segment on ipc).
TEST_P(CoupledRun, InPlaceBuffersCarryTheSameData) {
  zmq::context_t context;
  TempDir dir;
  const std::vector<std::uint32_t> cells{1002, 642};
  FluidSide fluid({test_scene(2), fluid_endpoints(GetParam(), 1, dir), {}, test_options()},
                  context);
  std::vector<std::vector<double>> got;
  std::thread membrane_thread([&] {
    MembraneSide m(
        {test_scene(2), fluid.endpoints()[0], "membrane-0", 0, 1, 0, cells, test_options()},
        context);
    m.initialize();
    std::vector<double> x(3 * m.node_count()), f(x.size());
    for (int s = 0; s < 3; ++s) {
      fill_nodes(m.step(), 0, x, f);
      std::copy(x.begin(), x.end(), m.positions_buffer().begin());
      std::copy(f.begin(), f.end(), m.forces_buffer().begin());
      const auto u = m.exchange(m.positions_buffer(), m.forces_buffer());
      ASSERT_TRUE(u.has_value());
      got.emplace_back(u->begin(), u->end());
    }
    m.finalize();
  });
  fluid.initialize();
  std::vector<double> u;
  while (fluid.receive()) {
    dummy_velocities(fluid.step(), fluid.positions(), fluid.forces(), u);
    std::copy(u.begin(), u.end(), fluid.velocities_buffer().begin());
    fluid.send_velocities(fluid.velocities_buffer());
  }
  fluid.finalize();
  membrane_thread.join();
  ASSERT_EQ(got.size(), 3u);
  for (int s = 0; s < 3; ++s) {
    std::vector<double> x(3 * (1002 + 642)), f(x.size()), expected;
    fill_nodes(s, 0, x, f);
    dummy_velocities(s, x, f, expected);
    EXPECT_TRUE(bit_equal(got[s], expected)) << "step " << s;
  }
}

INSTANTIATE_TEST_SUITE_P(Transports, CoupledRun,
                         ::testing::Values(Kind::inproc, Kind::ipc, Kind::tcp),
                         [](const auto& p) { return name(p.param); });

TEST(CoupledRun, TransportsGiveIdenticalRuns) {
  const std::vector<std::vector<std::uint32_t>> split{{1002, 1002}, {642}};
  const RunRecord a = run_coupled(Kind::inproc, split, 3);
  for (Kind kind : {Kind::ipc, Kind::tcp}) {
    const RunRecord b = run_coupled(kind, split, 3);
    ASSERT_EQ(b.fluid_positions.size(), a.fluid_positions.size()) << name(kind);
    for (std::size_t s = 0; s < a.fluid_positions.size(); ++s) {
      EXPECT_TRUE(bit_equal(a.fluid_positions[s], b.fluid_positions[s])) << name(kind);
      EXPECT_TRUE(bit_equal(a.fluid_forces[s], b.fluid_forces[s])) << name(kind);
    }
    for (std::size_t k = 0; k < split.size(); ++k) {
      ASSERT_EQ(a.membrane_velocities[k].size(), b.membrane_velocities[k].size());
      for (std::size_t s = 0; s < a.membrane_velocities[k].size(); ++s) {
        EXPECT_TRUE(bit_equal(a.membrane_velocities[k][s], b.membrane_velocities[k][s]))
            << name(kind);
      }
    }
  }
}

TEST(CoupledRun, IpcFramesWhenEitherSideRefusesSharedMemory) {
  const std::vector<std::vector<std::uint32_t>> split{{1002}, {642, 12}};
  for (const auto& [fluid_shm, membrane_shm] : {std::pair{false, true}, std::pair{true, false}}) {
    const RunRecord rec = run_coupled(Kind::ipc, split, 3, fluid_shm, membrane_shm);
    expect_exact(rec, split, 3);
    for (int shared : rec.shared_memory) EXPECT_EQ(shared, 0);
  }
}

TEST(CoupledRun, SharedMemoryLeavesNoSegmentBehind) {
  run_coupled(Kind::ipc, {{100}}, 2);
  const std::string prefix = "dld-coupler-" + std::to_string(getpid()) + "-";
  for (const auto& entry : std::filesystem::directory_iterator("/dev/shm")) {
    EXPECT_FALSE(entry.path().filename().string().starts_with(prefix)) << entry.path();
  }
}

TEST(CoupledRun, FluidEndsTheRunAndTheMembraneSeesIt) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
                  context);
  bool advanced = true;
  std::uint64_t membrane_step = 0;
  std::thread membrane_thread([&] {
    MembraneSide m(
        {test_scene(1), fluid.endpoints()[0], "membrane-0", 0, 1, 0, {5}, test_options()}, context);
    m.initialize();
    std::vector<double> x(15, 1.0), f(15, 0.0), u(15);
    while ((advanced = m.advance(x, f, u))) {
    }
    membrane_step = m.step();
    EXPECT_EQ(m.state(), State::ended);
    m.finalize();
  });
  fluid.initialize();
  for (int s = 0; s < 3; ++s) {
    ASSERT_TRUE(fluid.receive());
    fluid.send_velocities(std::vector<double>(15, 0.25));
  }
  ASSERT_TRUE(fluid.receive());  // step 3 received, then the fluid stops (e.g. Ctrl-C)
  fluid.finalize();
  membrane_thread.join();
  EXPECT_FALSE(advanced);
  EXPECT_EQ(membrane_step, 3u);
}

TEST(CoupledRun, RestartStartsAtTheAgreedStep) {
  zmq::context_t context;
  TempDir dir;
  SceneIdentity scene = test_scene(1);
  scene.start_step = 1000;
  FluidSide fluid({scene, fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()}, context);
  std::thread membrane_thread([&] {
    MembraneSide m({scene, fluid.endpoints()[0], "membrane-0", 0, 1, 0, {2}, test_options()},
                   context);
    m.initialize();
    std::vector<double> x(6, 1.0), f(6, 0.0), u(6);
    EXPECT_TRUE(m.advance(x, f, u));
    EXPECT_EQ(m.step(), 1001u);
    m.finalize();
  });
  fluid.initialize();
  ASSERT_TRUE(fluid.receive());
  EXPECT_EQ(fluid.step(), 1000u);
  fluid.send_velocities(std::vector<double>(6, 0.0));
  EXPECT_FALSE(fluid.receive());
  fluid.finalize();
  membrane_thread.join();
}

}  // namespace
}  // namespace dld::coupler::test

namespace dld::coupler::test {
namespace {

struct Party {
  std::string public_key, secret_key;
};

Party party() {
  char pub[41], sec[41];
  if (zmq_curve_keypair(pub, sec) != 0) throw std::runtime_error("zmq_curve_keypair failed");
  return {pub, sec};
}

Options server_options(const Party& server, const std::vector<Party>& admitted,
                       std::chrono::milliseconds timeout = 30'000ms) {
  Options o = test_options(timeout);
  o.curve = CurveKeys{server.public_key, server.secret_key, "", "", {}};
  for (const Party& c : admitted) o.curve->client_publics.push_back(c.public_key);
  return o;
}

Options client_options(const std::string& server_public, const Party& client,
                       std::chrono::milliseconds timeout = 30'000ms) {
  Options o = test_options(timeout);
  o.curve = CurveKeys{server_public, "", client.public_key, client.secret_key, {}};
  return o;
}

/// One step of a one-cell run between the fluid and a membrane with these options; the
/// velocities the membrane received equal the ones sent.
void expect_one_exact_step(FluidSide& fluid, const Options& membrane_options) {
  std::vector<double> received;
  std::thread membrane_thread([&] {
    MembraneSide m(
        {test_scene(1), fluid.endpoints()[0], "membrane-0", 0, 1, 0, {3}, membrane_options});
    m.initialize();
    std::vector<double> x(9), f(9, 0.5), u(9);
    fill_nodes(0, 0, x, f);
    ASSERT_TRUE(m.advance(x, f, u));
    received = u;
    m.finalize();
  });
  fluid.initialize();
  ASSERT_TRUE(fluid.receive());
  std::vector<double> u;
  dummy_velocities(0, fluid.positions(), fluid.forces(), u);
  fluid.send_velocities(u);
  EXPECT_FALSE(fluid.receive());
  fluid.finalize();
  membrane_thread.join();
  EXPECT_EQ(received, u);
}

TEST(Curve, AuthenticatedTcpRunIsBitExact) {
  if (!zmq_has("curve")) GTEST_SKIP() << "libzmq built without CURVE";
  const Party server = party(), client = party();
  FluidSide fluid({test_scene(1), {"tcp://127.0.0.1:*"}, {}, server_options(server, {client})});
  expect_one_exact_step(fluid, client_options(server.public_key, client));
  EXPECT_TRUE(fluid.refused_clients().empty());
}

/// An intruder connects first: it is refused, named in the fluid's refusals (its log), and the
/// run's own membrane still gets in afterwards.
void expect_refused_then_run(const std::function<Options(const Party& server)>& intruder,
                             const std::string& why) {
  const Party server = party(), client = party();
  FluidSide fluid({test_scene(1), {"tcp://127.0.0.1:*"}, {}, server_options(server, {client})});
  {
    MembraneSide rogue({test_scene(1),
                        fluid.endpoints()[0],
                        "rogue",
                        0,
                        1,
                        0,
                        {3},
                        intruder(server)});  // connects: the handshake starts at once
    const auto until = std::chrono::steady_clock::now() + 5s;
    while (fluid.refused_clients().empty() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(10ms);
  }
  const auto refused = fluid.refused_clients();
  ASSERT_FALSE(refused.empty()) << "no refusal logged";
  EXPECT_NE(refused[0].find(why), std::string::npos) << refused[0];
  EXPECT_EQ(refused[0].rfind("fluid: refused a client", 0), 0u) << refused[0];
  expect_one_exact_step(fluid, client_options(server.public_key, client));
}

TEST(Curve, KeylessClientIsRefusedAndNamed) {
  if (!zmq_has("curve")) GTEST_SKIP() << "libzmq built without CURVE";
  expect_refused_then_run([](const Party&) { return test_options(); }, "no CURVE keys");
}

TEST(Curve, MadeUpKeyPairIsRefusedAndNamed) {
  if (!zmq_has("curve")) GTEST_SKIP() << "libzmq built without CURVE";
  const Party stranger = party();
  expect_refused_then_run(
      [&](const Party& server) { return client_options(server.public_key, stranger); },
      "its key " + stranger.public_key + " is not among the run's client keys");
}

TEST(Curve, WrongServerKeyIsRefusedAndNamed) {
  if (!zmq_has("curve")) GTEST_SKIP() << "libzmq built without CURVE";
  const Party client = party(), other_server = party();
  expect_refused_then_run(
      [&](const Party&) { return client_options(other_server.public_key, client); },
      "does not decrypt");
}

TEST(Curve, WrongServerKeyNeverGetsIn) {
  if (!zmq_has("curve")) GTEST_SKIP() << "libzmq built without CURVE";
  const Party server = party(), client = party(), other = party();
  FluidSide fluid(
      {test_scene(1), {"tcp://127.0.0.1:*"}, {}, server_options(server, {client}, 300ms)});
  std::thread membrane_thread([&] {
    MembraneSide m({test_scene(1),
                    fluid.endpoints()[0],
                    "membrane-0",
                    0,
                    1,
                    0,
                    {3},
                    client_options(other.public_key, client, 300ms)});
    EXPECT_THROW(m.initialize(), CouplerError);
  });
  EXPECT_THROW(fluid.initialize(), CouplerError);  // no hello ever arrives
  membrane_thread.join();
}

}  // namespace
}  // namespace dld::coupler::test
