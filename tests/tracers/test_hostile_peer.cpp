// SPDX-License-Identifier: MIT
// dld-fluid against a membrane peer that sends what no membrane model would: non-finite forces
// (refused as a malformed frame) and forces the lattice cannot take (the run stops at that step,
// naming the peer). Either way dld-fluid exits non-zero and writes no checkpoint of the state.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/membrane_side.hpp"
#include "coupler/scene_identity.hpp"
#include "shared/scene.hpp"
#include "tests/child_process.hpp"
#include "tests/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using dld::test::slurp;
using dld::test::spawn;
using dld::test::wait_for;

class HostilePeer : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = (dir_ / "scene.toml").string();
    std::ofstream(scene_) << "[scene]\nname = \"hostile\"\n[geometry]\npillar_radius_um = 10.0\n"
                             "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
                             "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n[run]\nthreads = "
                             "1\n[output]\nfields = false\n[coupling]\ntimeout_s = 20\n";
  }

  /// Runs dld-fluid against an in-test membrane of 4 nodes that sends `force` on every node for
  /// up to 3 steps; returns what the membrane side was told (its CouplerError) and leaves the
  /// fluid's exit code in fluid_rc_.
  std::string run_with_force(double force, const std::function<void(int)>& before_step = {}) {
    const std::string endpoint = "ipc://" + (dir_ / "sock").string();
    dld::test::Process fluid = spawn(
        {DLD_FLUID_EXE, scene_, "--serve", endpoint, "--cells", "1", "-o",
         (dir_ / "fluid.h5").string(), "--checkpoint", checkpoint(), "--checkpoint-every", "1"},
        (dir_ / "fluid.log").string());
    const dld::Scene scene = dld::load_scene(scene_);
    dld::coupler::MembraneSide membrane({dld::coupler::scene_identity(scene, 1),
                                         dld::coupler::peer_endpoints(endpoint, 1)[0],
                                         "membrane-0",
                                         0,
                                         1,
                                         0,
                                         {4},
                                         {}});
    std::string told = "nothing";
    try {
      membrane.initialize();
      // Four markers in the open channel below the pillar (lattice units).
      const std::vector<double> x{4, 3, 3, 5, 3, 3, 4, 4, 3, 5, 4, 3};
      const std::vector<double> f(x.size(), force);
      std::vector<double> u(x.size());
      for (int s = 0; s < 3; ++s) {
        if (before_step) before_step(s);
        if (!membrane.advance(x, f, u)) break;
      }
      membrane.finalize();
    } catch (const dld::coupler::CouplerError& e) {
      told = e.what();
    }
    fluid_rc_ = wait_for(fluid, 30);
    fluid_log_ = slurp(fluid.log);
    return told;
  }
  std::string checkpoint() const { return (dir_ / "fluid.ckpt.h5").string(); }

  dld::test::TempDir tmp_{"dld-hostile"};
  const fs::path& dir_ = tmp_.path();
  std::string scene_, fluid_log_;
  int fluid_rc_ = -1;
};

TEST_F(HostilePeer, NonFiniteForcesAreRefusedNamingTheFieldAndNoCheckpointIsWritten) {
  const std::string told = run_with_force(std::nan(""));
  EXPECT_NE(told.find("field 'forces': node 0 has a non-finite value (nan)"), std::string::npos)
      << told;
  EXPECT_NE(fluid_rc_, 0) << fluid_log_;
  EXPECT_NE(fluid_log_.find("membrane 'membrane-0'"), std::string::npos) << fluid_log_;
  EXPECT_FALSE(fs::exists(checkpoint()));
}

TEST_F(HostilePeer, ForcesTheLatticeCannotTakeStopTheRunAtThatStep) {
  const std::string told = run_with_force(1e10);
  EXPECT_NE(told.find("lattice cannot take the forces"), std::string::npos) << told;
  EXPECT_NE(told.find("of membrane 'membrane-0' after step 1"), std::string::npos) << told;
  EXPECT_NE(fluid_rc_, 0) << fluid_log_;
  EXPECT_FALSE(fs::exists(checkpoint())) << "a checkpoint of the blown-up state";
}

// The same peer with ordinary forces runs and checkpoints (the two tests above are not vacuous).
TEST_F(HostilePeer, OrdinaryForcesRunAndCheckpoint) {
  const std::string told = run_with_force(1e-6);
  EXPECT_EQ(told, "nothing") << fluid_log_;
  EXPECT_EQ(fluid_rc_, 0) << fluid_log_;
  EXPECT_TRUE(fs::exists(checkpoint()));
}

/// Shrinks this process's shared-memory segment to `bytes` through /proc/self/map_files (its name
/// is gone after the welcome); false if this process may not open it (not root).
bool shrink_own_segment(off_t bytes) {
  std::ifstream maps("/proc/self/maps");
  std::string line;
  const std::string name = "/dev/shm/dld-coupler-" + std::to_string(getpid()) + "-";
  while (std::getline(maps, line)) {
    if (line.find(name) == std::string::npos) continue;
    const int fd = open(("/proc/self/map_files/" + line.substr(0, line.find(' '))).c_str(), O_RDWR);
    if (fd < 0) return false;
    const bool done = ftruncate(fd, bytes) == 0;
    close(fd);
    return done;
  }
  return false;
}

// A peer that shrinks its shared memory after the welcome (issue 18, item 4): the fluid stops
// with the peer and the segment named, not with a SIGBUS, and writes no checkpoint after it.
TEST_F(HostilePeer, ASharedSegmentShrunkAfterTheWelcomeIsAnErrorNotASignal) {
  bool shrunk = false;
  // 4 nodes: positions and forces are the first 192 bytes of 288, all in one page, so this
  // process can still write them; the fluid must notice the size, not touch a lost page.
  const std::string told = run_with_force(1e-6, [&](int step) {
    if (step == 1) shrunk = shrink_own_segment(192);
  });
  if (!shrunk) GTEST_SKIP() << "cannot open this process's shared memory (needs root)";
  EXPECT_NE(fluid_log_.find("membrane 'membrane-0' shrank its shared memory"), std::string::npos)
      << fluid_log_;
  EXPECT_NE(told.find("shrank its shared memory"), std::string::npos) << told;
  EXPECT_NE(fluid_rc_, 0) << fluid_log_;
  EXPECT_LT(fluid_rc_, 128) << "killed by a signal: " << fluid_log_;
}

}  // namespace
