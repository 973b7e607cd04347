// SPDX-License-Identifier: MIT
// Held steps (docs/protocol.md, issue 13): a membrane that holds its forces for n steps sends
// them once with n; the fluid sees n from every peer, runs the steps and answers with positions,
// and the step count moves by n. Peers that disagree on n stop the run naming both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <span>
#include <thread>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

bool bit_equal(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

/// The dummy fluid's answer to held steps: the positions moved by a step-dependent amount.
std::vector<double> moved(std::span<const double> x, std::uint64_t step, std::uint64_t n) {
  std::vector<double> y(x.begin(), x.end());
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] += 0.25 * static_cast<double>(n) + 1e-3 * static_cast<double>(step + i);
  return y;
}

/// Membrane peers as threads, one per entry of `split` (its cells' node counts): each connects,
/// initializes and runs `body(side, k)`; what it throws ends up in errors[k].
struct Peers {
  std::vector<std::string> errors;
  std::vector<std::thread> threads;
  Peers(zmq::context_t& context, const FluidSide& fluid, std::uint32_t cells,
        const std::vector<std::vector<std::uint32_t>>& split,
        const std::function<void(MembraneSide&, std::uint32_t)>& body)
      : errors(split.size()) {
    const auto peers = static_cast<std::uint32_t>(split.size());
    std::uint32_t first = 0;
    for (std::uint32_t k = 0; k < peers; ++k) {
      threads.emplace_back([this, &context, &fluid, cells, peers, k, first, nodes = split[k],
                            body] {
        try {
          MembraneSide m({test_scene(cells), fluid.endpoints()[k], "membrane-" + std::to_string(k),
                          k, peers, first, nodes, test_options()},
                         context);
          m.initialize();
          body(m, k);
        } catch (const std::exception& e) {
          errors[k] = e.what();
        }
      });
      first += static_cast<std::uint32_t>(split[k].size());
    }
  }
  void join() {
    for (auto& t : threads) t.join();
  }
};

class HeldStepsOver : public ::testing::TestWithParam<Kind> {};

// Two peers: three held steps, then one step (velocities), then two held steps.
TEST_P(HeldStepsOver, PositionsComeBackAfterTheHeldStepsAndTheStepMovesByThem) {
  zmq::context_t context;
  TempDir dir;
  const std::vector<std::vector<std::uint32_t>> split{{1002, 642}, {12}};
  const std::vector<std::uint64_t> blocks{3, 1, 2};
  FluidSide fluid({test_scene(3), fluid_endpoints(GetParam(), 2, dir), {}, test_options()},
                  context);
  Peers membranes(context, fluid, 3, split, [&](MembraneSide& m, std::uint32_t k) {
    std::vector<double> x(3 * m.node_count()), f(x.size()), after(x.size());
    for (std::uint64_t n : blocks) {
      const std::uint64_t s = m.step();
      fill_nodes(s, k == 0 ? 0 : 1644, x, f);
      ASSERT_TRUE(m.advance_held(x, f, n, after));
      EXPECT_EQ(m.step(), s + n);
      std::vector<double> expected;
      if (n == 1) {  // velocities: the side adds them to the positions (X += U dt, dt = 1)
        std::vector<double> u;
        dummy_velocities(s, x, f, u);
        expected = x;
        for (std::size_t i = 0; i < x.size(); ++i) expected[i] = x[i] + u[i];
      } else {  // the fluid's positions, in this peer's slice of the concatenation
        std::vector<double> all(std::size_t{3} * 1656), unused(all.size());
        fill_nodes(s, 0, all, unused);
        const auto y = moved(all, s, n);
        const std::size_t first = k == 0 ? 0 : 3 * 1644;
        expected.assign(y.begin() + first, y.begin() + first + x.size());
      }
      EXPECT_TRUE(bit_equal(after, expected)) << "peer " << k << " from step " << s;
    }
    m.finalize();
  });
  fluid.initialize();
  std::vector<std::uint64_t> seen;
  std::vector<double> u;
  while (fluid.receive()) {
    seen.push_back(fluid.held_steps());
    std::vector<double> x(3 * fluid.node_count()), f(x.size());
    fill_nodes(fluid.step(), 0, x, f);
    EXPECT_TRUE(bit_equal(fluid.positions(), x)) << "step " << fluid.step();
    EXPECT_TRUE(bit_equal(fluid.forces(), f)) << "step " << fluid.step();
    if (fluid.held_steps() == 1) {
      EXPECT_THROW(fluid.send_positions(x), std::logic_error);
      dummy_velocities(fluid.step(), fluid.positions(), fluid.forces(), u);
      fluid.send_velocities(u);
    } else {
      EXPECT_THROW(fluid.send_velocities(x), std::logic_error);
      fluid.send_positions(moved(x, fluid.step(), fluid.held_steps()));
    }
  }
  EXPECT_EQ(fluid.step(), 6u);
  fluid.finalize();
  membranes.join();
  EXPECT_EQ(membranes.errors[0], "");
  EXPECT_EQ(membranes.errors[1], "");
  EXPECT_EQ(seen, blocks);
}

INSTANTIATE_TEST_SUITE_P(Transports, HeldStepsOver,
                         ::testing::Values(Kind::inproc, Kind::ipc, Kind::tcp),
                         [](const auto& p) { return name(p.param); });

TEST(HeldStepsProtocol, PeersThatDisagreeStopTheRunNamingBoth) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(2), fluid_endpoints(Kind::inproc, 2, dir), {}, test_options()},
                  context);
  Peers membranes(context, fluid, 2, {{10}, {10}}, [](MembraneSide& m, std::uint32_t k) {
    std::vector<double> x(30, 1.0), f(30, 0.5);
    (void)m.advance_held(x, f, k == 0 ? 3 : 2, x);
  });
  fluid.initialize();
  try {
    (void)fluid.receive();
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid: membrane 'membrane-0' holds its forces for 3 step(s) from step 0 and "
              "membrane 'membrane-1' for 2: membrane programs must hold the same steps");
  }
  membranes.join();
  for (const auto& e : membranes.errors)
    EXPECT_NE(e.find("must hold the same steps"), std::string::npos) << e;
}

TEST(HeldStepsProtocol, AMembraneRefusesVelocitiesForHeldSteps) {
  zmq::context_t context;
  RawPeer raw_fluid(context, "inproc://held-velocities", true);
  MembraneSide m({test_scene(1), raw_fluid.endpoint(), "membrane-0", 0, 1, 0, {2}, test_options()},
                 context);
  const std::vector<double> x(6, 1.5);
  std::thread fluid_thread([&] {
    ASSERT_TRUE(raw_fluid.receive());  // hello
    raw_fluid.send(encode_handshake(FrameType::welcome, hello_for(test_scene(1), {2}, "fluid")));
    auto steps = raw_fluid.receive();
    ASSERT_TRUE(steps);
    EXPECT_EQ(RawPeer::type_of(*steps), FrameType::held_steps);
    raw_fluid.send(encode_velocities(0, x));
    auto told = raw_fluid.receive();
    ASSERT_TRUE(told);
    EXPECT_EQ(RawPeer::type_of(*told), FrameType::error);
  });
  m.initialize();
  std::vector<double> after(6);
  try {
    (void)m.advance_held(x, x, 4, after);
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "membrane 'membrane-0': malformed frame from fluid at step 0: field 'type': expected "
              "positions, shutdown or error, got velocities");
  }
  fluid_thread.join();
}

TEST(HeldStepsProtocol, FrameRoundTripIsBitExact) {
  const std::vector<double> x{-0.0, 4.9e-324, 1.0 / 3.0, 1e308, -7.5, 2.0};
  const std::vector<double> f{1.0, 2.0, 3.0, 4.0, 5.0, -6.25};
  const zmq::message_t frame = encode_held_steps(42, 5, x, f);
  EXPECT_EQ(frame.size(), kHeaderBytes + held_steps_payload_bytes(2));
  const Link link{"fluid", "membrane"};
  const FrameHeader h = read_header(frame, link, 42);
  EXPECT_EQ(h.type, FrameType::held_steps);
  const HeldSteps held = read_held_steps(frame, h, 2, 2, link);
  EXPECT_EQ(held.steps, 5u);
  const auto bytes_x = std::as_bytes(std::span(x)), bytes_f = std::as_bytes(std::span(f));
  EXPECT_TRUE(std::equal(bytes_x.begin(), bytes_x.end(), held.data));
  EXPECT_TRUE(std::equal(bytes_f.begin(), bytes_f.end(), held.data + 48));
  const zmq::message_t shared = encode_held_steps_shared(42, 2, 7);
  EXPECT_EQ(read_held_steps(shared, read_header(shared, link, 42), 2, 0, link).steps, 7u);
}

}  // namespace
}  // namespace dld::coupler::test
