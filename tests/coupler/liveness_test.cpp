// SPDX-License-Identifier: MIT
// A peer that dies, hangs or fails stops the other side within the timeout, with a message that
// names the side and the step; error frames carry the failing side's message to everyone.
#include <gtest/gtest.h>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

constexpr auto kTimeout = 300ms;
constexpr auto kSlack = 1000ms;  // the machine is shared with compilers: generous upper bound

using Clock = std::chrono::steady_clock;

class Liveness : public ::testing::TestWithParam<Kind> {};

TEST_P(Liveness, FluidStopsWhenTheMembraneGoesSilent) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(GetParam(), 1, dir), {}, test_options(kTimeout)},
                  context);
  RawPeer raw(context, fluid.endpoints()[0], false);
  raw.send(encode_handshake(FrameType::hello, hello_for(test_scene(1), {10})));
  fluid.initialize();
  ASSERT_TRUE(raw.receive());  // welcome; then the membrane hangs
  const auto start = Clock::now();
  try {
    (void)fluid.receive();
    FAIL() << "no timeout";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid: no frame from membrane 'raw' within 0.3 s while waiting for step 0 (peer "
              "dead or hung?)");
  }
  const auto waited = Clock::now() - start;
  EXPECT_GE(waited, kTimeout - 20ms);  // poll rounds to the clock tick
  EXPECT_LT(waited, kTimeout + kSlack);
}

TEST_P(Liveness, MembraneStopsWhenTheFluidHangsMidStep) {
  zmq::context_t context;
  TempDir dir;
  RawPeer raw_fluid(context, fluid_endpoints(GetParam(), 1, dir)[0], true);
  MembraneSide m(
      {test_scene(1), raw_fluid.endpoint(), "membrane-0", 0, 1, 0, {10}, test_options(kTimeout)},
      context);
  std::thread fluid_thread([&] {
    ASSERT_TRUE(raw_fluid.receive());  // hello
    raw_fluid.send(encode_handshake(FrameType::welcome, hello_for(test_scene(1), {10}, "fluid")));
    ASSERT_TRUE(raw_fluid.receive());  // step 0; then the fluid hangs
  });
  m.initialize();
  std::vector<double> v(30, 1.0), u(30);
  const auto start = Clock::now();
  try {
    (void)m.advance(v, v, u);
    FAIL() << "no timeout";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "membrane 'membrane-0': no velocities from the fluid within 0.45 s at step 0 (fluid "
              "dead or hung?)");
  }
  // The membrane waits half a timeout longer than the fluid, so that the fluid's own diagnosis
  // (another membrane dead or hung) reaches it first.
  const auto waited = Clock::now() - start;
  EXPECT_GE(waited, kTimeout * 3 / 2 - 20ms);  // poll rounds to the clock tick
  EXPECT_LT(waited, kTimeout * 3 / 2 + kSlack);
  fluid_thread.join();
}

INSTANTIATE_TEST_SUITE_P(Transports, Liveness,
                         ::testing::Values(Kind::inproc, Kind::ipc, Kind::tcp),
                         [](const auto& p) { return name(p.param); });

TEST(Liveness, HandshakeTimesOutWhenNoMembraneComes) {
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::ipc, 1, dir), {}, test_options(kTimeout)});
  const auto start = Clock::now();
  try {
    fluid.initialize();
    FAIL() << "no timeout";
  } catch (const CouplerError& e) {
    EXPECT_NE(std::string(e.what()).find("fluid: no hello from membrane peer 0 on 'ipc://"),
              std::string::npos)
        << e.what();
  }
  EXPECT_LT(Clock::now() - start, kTimeout + kSlack);
}

TEST(Liveness, HandshakeTimesOutWhenNoFluidComes) {
  TempDir dir;
  MembraneSide m({test_scene(1),
                  "ipc://" + (dir.path() / "nobody").string(),
                  "membrane-0",
                  0,
                  1,
                  0,
                  {10},
                  test_options(kTimeout)});
  const auto start = Clock::now();
  EXPECT_THROW(m.initialize(), CouplerError);
  EXPECT_LT(Clock::now() - start, kTimeout + kSlack);
}

TEST(ErrorFrame, MembraneAbortStopsTheFluidAndTheOtherPeers) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(2), fluid_endpoints(Kind::inproc, 2, dir), {}, test_options()},
                  context);
  std::string peer0_error;
  std::thread peer0([&] {
    MembraneSide m(
        {test_scene(2), fluid.endpoints()[0], "membrane-0", 0, 2, 0, {4}, test_options()}, context);
    m.initialize();
    std::vector<double> v(12, 1.0), u(12);
    try {
      while (m.advance(v, v, u)) {
      }
    } catch (const CouplerError& e) {
      peer0_error = e.what();
    }
  });
  std::thread peer1([&] {
    MembraneSide m(
        {test_scene(2), fluid.endpoints()[1], "membrane-1", 1, 2, 1, {4}, test_options()}, context);
    m.initialize();
    std::vector<double> v(12, 1.0), u(12);
    for (int s = 0; s < 2; ++s) ASSERT_TRUE(m.advance(v, v, u));
    m.abort("cell 1: volume drift 12 % exceeds 0.5 %");
  });
  fluid.initialize();
  std::string fluid_error;
  try {
    std::vector<double> u(24, 0.0);
    while (fluid.receive()) fluid.send_velocities(u);
  } catch (const CouplerError& e) {
    fluid_error = e.what();
  }
  peer0.join();
  peer1.join();
  const std::string expected =
      "fluid: membrane 'membrane-1' reported an error at step 2: cell 1: volume drift 12 % "
      "exceeds 0.5 %";
  EXPECT_EQ(fluid_error, expected);
  EXPECT_EQ(peer0_error, "membrane 'membrane-0': fluid reported an error at step 2: " + expected);
}

TEST(ErrorFrame, FluidAbortStopsTheMembrane) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::ipc, 1, dir), {}, test_options()}, context);
  std::string membrane_error;
  std::thread membrane([&] {
    MembraneSide m(
        {test_scene(1), fluid.endpoints()[0], "membrane-0", 0, 1, 0, {4}, test_options()}, context);
    m.initialize();
    std::vector<double> v(12, 1.0), u(12);
    try {
      while (m.advance(v, v, u)) {
      }
    } catch (const CouplerError& e) {
      membrane_error = e.what();
    }
  });
  fluid.initialize();
  ASSERT_TRUE(fluid.receive());
  fluid.send_velocities(std::vector<double>(12, 0.0));
  ASSERT_TRUE(fluid.receive());
  fluid.abort("lattice unstable: density 3.2 at (10, 4, 2)");
  EXPECT_EQ(fluid.state(), State::failed);
  membrane.join();
  EXPECT_EQ(membrane_error,
            "membrane 'membrane-0': fluid reported an error at step 1: lattice unstable: density "
            "3.2 at (10, 4, 2)");
  fluid.finalize();
}

TEST(ErrorFrame, ClosingWithoutFinalizeIsReportedAtOnce) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options(5000ms)},
                  context);
  std::thread membrane([&] {
    MembraneSide m(
        {test_scene(1), fluid.endpoints()[0], "membrane-0", 0, 1, 0, {4}, test_options(5000ms)},
        context);
    m.initialize();
    std::vector<double> v(12, 1.0), u(12);
    ASSERT_TRUE(m.advance(v, v, u));
    // m goes out of scope as if an exception unwound the membrane program
  });
  fluid.initialize();
  ASSERT_TRUE(fluid.receive());
  fluid.send_velocities(std::vector<double>(12, 0.0));
  const auto start = Clock::now();
  try {
    (void)fluid.receive();
    FAIL() << "no error";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid: membrane 'membrane-0' reported an error at step 1: membrane 'membrane-0' "
              "closed without finalize() at step 1");
  }
  EXPECT_LT(Clock::now() - start, 2000ms);
  membrane.join();
}

}  // namespace
}  // namespace dld::coupler::test
