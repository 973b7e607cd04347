// SPDX-License-Identifier: MIT
// A peer process that is killed (SIGKILL: it sends nothing) stops the other side within the
// timeout, over ipc between two real processes.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

constexpr auto kTimeout = 500ms;
constexpr auto kSlack = 1500ms;
using Clock = std::chrono::steady_clock;

Options dead_peer_options() {
  Options o = test_options(kTimeout);
  o.handshake_timeout = 10'000ms;  // the other process may be slow to start on a loaded machine
  return o;
}

// Forked before any ZeroMQ context exists in this process, so the child starts clean; it leaves
// with _exit so that nothing of the test framework runs twice.
template <class Body>
pid_t spawn(Body body) {
  const pid_t child = fork();
  if (child == 0) {
    try {
      body();
    } catch (...) {
    }
    _exit(0);
  }
  return child;
}

TEST(DeadPeer, KilledMembraneProcessStopsTheFluid) {
  TempDir dir;
  const std::string endpoint = "ipc://" + (dir.path() / "coupler").string();
  const pid_t child = spawn([&] {
    MembraneSide m({test_scene(1), endpoint, "membrane-0", 0, 1, 0, {100}, dead_peer_options()});
    m.initialize();
    std::vector<double> x(300, 1.0), f(300, 0.0), u(300);
    for (int s = 0; s < 100'000 && m.advance(x, f, u); ++s) {
    }
  });
  ASSERT_GT(child, 0);
  FluidSide fluid({test_scene(1), {endpoint}, {}, dead_peer_options()});
  fluid.initialize();
  for (int s = 0; s < 3; ++s) {
    ASSERT_TRUE(fluid.receive());
    fluid.send_velocities(std::vector<double>(300, 0.0));
  }
  ASSERT_TRUE(fluid.receive());  // step 3 is in; the membrane process dies while we compute
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  const auto start = Clock::now();
  try {
    fluid.send_velocities(std::vector<double>(300, 0.0));
    (void)fluid.receive();
    FAIL() << "the fluid did not notice";
  } catch (const CouplerError& e) {
    EXPECT_NE(std::string(e.what()).find("membrane 'membrane-0'"), std::string::npos) << e.what();
    // Either the velocities of step 3 find no taker, or step 4 never comes: both are named.
    const std::string what = e.what();
    EXPECT_TRUE(what.find("step 3") != std::string::npos ||
                what.find("step 4") != std::string::npos)
        << what;
  }
  EXPECT_LT(Clock::now() - start, kTimeout + kSlack);
}

TEST(DeadPeer, KilledFluidProcessStopsTheMembrane) {
  TempDir dir;
  const std::string endpoint = "ipc://" + (dir.path() / "coupler").string();
  const pid_t child = spawn([&] {
    FluidSide fluid({test_scene(1), {endpoint}, {}, dead_peer_options()});
    fluid.initialize();
    for (int s = 0; s < 100'000 && fluid.receive(); ++s) {
      fluid.send_velocities(std::vector<double>(300, 0.0));
    }
  });
  ASSERT_GT(child, 0);
  MembraneSide m({test_scene(1), endpoint, "membrane-0", 0, 1, 0, {100}, dead_peer_options()});
  m.initialize();
  std::vector<double> x(300, 1.0), f(300, 0.0), u(300);
  for (int s = 0; s < 3; ++s) ASSERT_TRUE(m.advance(x, f, u));
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  const auto start = Clock::now();
  try {
    (void)m.advance(x, f, u);
    FAIL() << "the membrane did not notice";
  } catch (const CouplerError& e) {
    EXPECT_NE(std::string(e.what()).find("membrane 'membrane-0'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("step 3"), std::string::npos) << e.what();
  }
  EXPECT_LT(Clock::now() - start, kTimeout + kSlack);
}

}  // namespace
}  // namespace dld::coupler::test
