// SPDX-License-Identifier: MIT
// The lock-step state machine refuses calls out of order with std::logic_error, never UB.
#include <gtest/gtest.h>

#include <stdexcept>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

std::string logic_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "(no logic_error)";
}

struct Pair {
  zmq::context_t context;
  TempDir dir;
  std::unique_ptr<FluidSide> fluid;
  std::unique_ptr<MembraneSide> membrane;
  Pair() {
    fluid = std::make_unique<FluidSide>(
        FluidConfig{test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
        context);
    membrane = std::make_unique<MembraneSide>(
        MembraneConfig{
            test_scene(1), fluid->endpoints()[0], "membrane-0", 0, 1, 0, {4}, test_options()},
        context);
  }
  void initialize() {
    std::thread t([&] { membrane->initialize(); });
    fluid->initialize();
    t.join();
  }
};

TEST(CallOrder, BeforeInitializeIsRefused) {
  Pair p;
  std::vector<double> v(12);
  EXPECT_EQ(logic_error_of([&] { (void)p.membrane->advance(v, v, v); }),
            "membrane 'membrane-0': advance() called before initialize()");
  EXPECT_EQ(logic_error_of([&] { (void)p.fluid->receive(); }),
            "fluid: receive() called before initialize()");
  EXPECT_EQ(logic_error_of([&] { p.fluid->send_velocities(v); }),
            "fluid: send_velocities() called before initialize()");
  EXPECT_EQ(logic_error_of([&] { p.fluid->finalize(); }),
            "fluid: finalize() called before initialize()");
  EXPECT_EQ(logic_error_of([&] { p.membrane->finalize(); }),
            "membrane 'membrane-0': finalize() called before initialize()");
}

TEST(CallOrder, InitializeTwiceIsRefused) {
  Pair p;
  p.initialize();
  EXPECT_EQ(logic_error_of([&] { p.fluid->initialize(); }), "fluid: initialize() called twice");
  EXPECT_EQ(logic_error_of([&] { p.membrane->initialize(); }),
            "membrane 'membrane-0': initialize() called twice");
  p.membrane->finalize();
  p.fluid->finalize();
}

TEST(CallOrder, FluidMustReceiveBeforeReplyingAndReplyBeforeReceiving) {
  Pair p;
  p.initialize();
  std::vector<double> v(12, 1.0), u(12);
  EXPECT_NE(logic_error_of([&] { p.fluid->send_velocities(v); }).find("call receive() first"),
            std::string::npos);
  EXPECT_THROW((void)p.fluid->positions(), std::logic_error);
  std::thread t([&] { EXPECT_TRUE(p.membrane->advance(v, v, u)); });
  ASSERT_TRUE(p.fluid->receive());
  EXPECT_EQ(logic_error_of([&] { (void)p.fluid->receive(); }),
            "fluid: receive() called while a received step awaits send_velocities()");
  EXPECT_THROW(p.fluid->send_velocities(std::vector<double>(6)), std::invalid_argument);
  p.fluid->send_velocities(v);
  t.join();
  p.membrane->finalize();
  EXPECT_FALSE(p.fluid->receive());
  EXPECT_EQ(logic_error_of([&] { (void)p.fluid->receive(); }),
            "fluid: receive() called after the peer ended the run");
  p.fluid->finalize();
}

TEST(CallOrder, AfterFinalizeIsRefused) {
  Pair p;
  p.initialize();
  p.membrane->finalize();
  EXPECT_FALSE(p.fluid->receive());
  p.fluid->finalize();
  std::vector<double> v(12);
  EXPECT_EQ(logic_error_of([&] { (void)p.membrane->advance(v, v, v); }),
            "membrane 'membrane-0': advance() called after finalize()");
  EXPECT_EQ(logic_error_of([&] { p.membrane->finalize(); }),
            "membrane 'membrane-0': finalize() called after finalize()");
  EXPECT_EQ(logic_error_of([&] { (void)p.fluid->receive(); }),
            "fluid: receive() called after finalize()");
}

TEST(CallOrder, WrongArraySizesAreRefused) {
  Pair p;
  p.initialize();
  std::vector<double> v(12), shorter(9);
  EXPECT_THROW((void)p.membrane->advance(shorter, v, v), std::invalid_argument);
  EXPECT_THROW((void)p.membrane->advance(v, v, shorter), std::invalid_argument);
  p.membrane->finalize();
  EXPECT_FALSE(p.fluid->receive());
  p.fluid->finalize();
}

TEST(CallOrder, AfterAnErrorOnlyFinalizeIsAllowed) {
  Pair p;
  p.initialize();
  p.membrane->abort("membrane solver diverged");
  EXPECT_THROW((void)p.fluid->receive(), CouplerError);
  EXPECT_EQ(logic_error_of([&] { (void)p.fluid->receive(); }),
            "fluid: receive() called after a coupling error");
  std::vector<double> v(12);
  EXPECT_EQ(logic_error_of([&] { (void)p.membrane->advance(v, v, v); }),
            "membrane 'membrane-0': advance() called after a coupling error");
  p.fluid->finalize();
  p.membrane->finalize();
}

}  // namespace
}  // namespace dld::coupler::test
