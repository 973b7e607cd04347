// SPDX-License-Identifier: MIT
// dld-fluid and dld-tracers as two processes over ipc: a run completes, a killed peer stops the
// other side within the timeout naming it, and a scene mismatch stops both naming the field.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "shared/dld_geometry.hpp"
#include "shared/h5file.hpp"
#include "tests/child_process.hpp"

namespace {

namespace fs = std::filesystem;

using dld::test::Process;
using dld::test::slurp;
using dld::test::spawn;
using dld::test::wait_for;

class TracersCoupled : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dld-tracers-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string scene(double dx, double timeout_s) {
    std::string path = (dir_ / ("scene-" + std::to_string(dx) + ".toml")).string();
    std::ofstream(path) << "[scene]\nname = \"tracers\"\n[geometry]\npillar_radius_um = 10.0\n"
                           "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
                           "[lattice]\ndx_um = "
                        << dx
                        << "\n[drive]\nreynolds = 0.1\n"
                           "[run]\nlog_every = 500\n[output]\nfields = false\n"
                           "[coupling]\ntimeout_s = "
                        << timeout_s << "\n";
    return path;
  }
  std::string endpoint() const { return "ipc://" + (dir_ / "sock").string(); }
  /// One red blood cell (500 faces) in the DLD cell at dx = 0.8 um; run file <dir>/<name>.h5.
  /// One-cell scene; `extra` goes at the end of [coupling], `fluid` is the [fluid] table's body.
  std::string cell_scene(const std::string& name, const std::string& extra = "",
                         const std::string& fluid = "") {
    std::string sc = (dir_ / (name + ".toml")).string();
    std::ofstream(sc)
        << "[scene]\nname = \"" << name
        << "\"\n[geometry]\npillar_radius_um = 10.0\n"
           "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
           "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n[run]\nthreads = 1\nlog_every = 100\n"
        << "[fluid]\n"
        << fluid << "[output]\nfields = false\nfile = \"" << (dir_ / (name + ".h5")).string()
        << "\"\n[coupling]\ntimeout_s = 20\n"
        << extra
        << "[membrane]\nradius_um = 3.9\nmesh_faces = 500\nmodels = [\"skalak\", \"bending\", "
           "\"volume\"]\ncapillary_number = 0.2\nmesh_cache = \""
        << (dir_ / "meshes").string()
        << "\"\n"
           "[membrane.skalak]\narea_modulus_ref_lu = 0.5\n[membrane.bending]\nmodulus_rel = "
           "2.5e-3\n[membrane.volume]\nmodulus_rel = 1000.0\n[membrane.contact]\nrange_um = 0.8\n"
           "strength_rel = 1.0\n[[cells.cell]]\ncentre_um = [3.0, 3.0, 2.4]\n";
    return sc;
  }
  /// dld-run on a cell scene with `extra` arguments; expects success.
  static void run(const std::string& sc, const std::vector<std::string>& extra) {
    std::vector<std::string> args{DLD_RUN_EXE, sc, "--membrane", "cells"};
    args.insert(args.end(), extra.begin(), extra.end());
    Process p = spawn(args, sc + ".log");
    EXPECT_EQ(wait_for(p, 240), 0) << slurp(p.log);
  }
  static std::vector<double> read(const std::string& path, const std::string& name) {
    dld::H5File f(path, dld::H5File::Mode::kRead);
    return f.read(name);
  }
  /// Largest |a_i - b_i| of the final nodes of two cell runs (their checkpoints).
  double node_difference(const std::string& a, const std::string& b) const {
    const auto xa = read((dir_ / (a + "-cells-0.ckpt.h5")).string(), "/membrane/positions");
    const auto xb = read((dir_ / (b + "-cells-0.ckpt.h5")).string(), "/membrane/positions");
    EXPECT_EQ(xa.size(), xb.size());
    double worst = 0;
    for (std::size_t i = 0; i < std::min(xa.size(), xb.size()); ++i)
      worst = std::max(worst, std::abs(xa[i] - xb[i]));
    return worst;
  }
  fs::path dir_;
};

TEST_F(TracersCoupled, RunCompletesAndTracersFollowTheFlow) {
  const std::string sc = scene(0.8, 30.0), out = (dir_ / "tracers.h5").string();
  Process fluid = spawn({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--cells", "6"},
                        (dir_ / "fluid.log").string());
  Process tracers = spawn(
      {DLD_TRACERS_EXE, sc, "--connect", endpoint(), "--count", "6", "--steps", "3000", "-o", out},
      (dir_ / "tracers.log").string());
  EXPECT_EQ(wait_for(tracers, 120), 0) << slurp(tracers.log);
  EXPECT_EQ(wait_for(fluid, 30), 0) << slurp(fluid.log);
  dld::H5File f(out, dld::H5File::Mode::kRead);
  std::vector<std::uint64_t> dims;
  const auto s = f.read("/tracers/samples", &dims);
  ASSERT_EQ(dims[1], 1u + 3 * 6);
  const std::size_t last = (dims[0] - 1) * dims[1];
  EXPECT_EQ(s[last], 3000.0);
  const dld::DldCell cell{32.0, 10.0, 4.8, 4.4};
  for (std::size_t m = 0; m < 6; ++m) {
    const double x0 = s[1 + 3 * m], x1 = s[last + 1 + 3 * m];
    EXPECT_GT(x1, x0) << "tracer " << m << " must move downstream";
    for (std::uint64_t r = 0; r < dims[0]; ++r) {
      const double* p = &s[r * dims[1] + 1 + 3 * m];
      const auto w = dld::wrap_into_box(cell, {p[0], p[1], p[2]});
      EXPECT_GT(cell.pillar_distance(w.position[0], w.position[1]), 0.0)
          << "tracer " << m << " in the pillar";
      EXPECT_GT(p[2], 0.0);
      EXPECT_LT(p[2], 4.8);
    }
  }
}

TEST_F(TracersCoupled, KilledPeerStopsTheFluidWithinTheTimeout) {
  const std::string sc = scene(0.8, 2.0);
  Process fluid = spawn({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--cells", "4"},
                        (dir_ / "fluid.log").string());
  Process tracers =
      spawn({DLD_TRACERS_EXE, sc, "--connect", endpoint(), "--count", "4", "--steps", "100000000"},
            (dir_ / "tracers.log").string());
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  kill(tracers.pid, SIGKILL);
  wait_for(tracers, 5);
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = wait_for(fluid, 10);
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_NE(rc, 0);
  EXPECT_NE(rc, -1) << "fluid hung";
  EXPECT_LT(waited, 5.0);
  const std::string log = slurp(fluid.log);
  EXPECT_NE(log.find("tracers-0"), std::string::npos) << log;
  EXPECT_NE(log.find("step"), std::string::npos) << log;
}

TEST_F(TracersCoupled, SceneMismatchStopsBothNamingTheField) {
  const std::string a = scene(0.8, 10.0), b = scene(0.4, 10.0);
  Process fluid = spawn({DLD_FLUID_EXE, a, "--serve", endpoint(), "--cells", "2"},
                        (dir_ / "fluid.log").string());
  Process tracers =
      spawn({DLD_TRACERS_EXE, b, "--connect", endpoint(), "--count", "2", "--steps", "10"},
            (dir_ / "tracers.log").string());
  EXPECT_NE(wait_for(tracers, 20), 0);
  EXPECT_NE(wait_for(fluid, 20), 0);
  const std::string lf = slurp(fluid.log), lt = slurp(tracers.log);
  EXPECT_NE(lf.find("handshake: field"), std::string::npos) << lf;
  EXPECT_NE(lt.find("handshake: field"), std::string::npos) << lt;
}

TEST_F(TracersCoupled, LauncherRunsTwoMembraneProcessesAndStopsCleanlyOnCtrlC) {
  std::string sc = scene(0.8, 5.0);
  std::ofstream(sc, std::ios::app) << "membrane_processes = 2\n";
  {  // output next to the test's files
    std::ifstream in(sc);
    std::stringstream t;
    t << in.rdbuf();
    std::string text = t.str();
    text.replace(text.find("[output]\n"), 9,
                 "[output]\nfile = \"" + (dir_ / "run.h5").string() + "\"\n");
    std::ofstream(sc) << text;
  }
  Process run = spawn({DLD_RUN_EXE, sc, "--tracers", "3", "--steps", "100000000"},
                      (dir_ / "run.log").string());
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  kill(run.pid, SIGINT);
  EXPECT_EQ(wait_for(run, 20), 130) << slurp(run.log);
  // Both membrane programs stopped at the same step and wrote their files.
  std::vector<double> last;
  for (int k = 0; k < 2; ++k) {
    dld::H5File f((dir_ / ("run-tracers-" + std::to_string(k) + ".h5")).string(),
                  dld::H5File::Mode::kRead);
    std::vector<std::uint64_t> dims;
    const auto s = f.read("/tracers/samples", &dims);
    last.push_back(s[(dims[0] - 1) * dims[1]]);
  }
  const std::string l0 = slurp((dir_ / "run-tracers-0.log").string());
  const std::string l1 = slurp((dir_ / "run-tracers-1.log").string());
  const auto steps_of = [](const std::string& log) {
    const auto p = log.find("tracers ran ");
    return p == std::string::npos ? std::string("?")
                                  : log.substr(p + 12, log.find(' ', p + 12) - p - 12);
  };
  EXPECT_EQ(steps_of(l0), steps_of(l1)) << l0 << l1;
  EXPECT_NE(steps_of(l0), "?") << l0;
  // After Ctrl-C too, the run file holds every part: the tracers of both processes and the
  // fluid's time series, equal to the part files.
  EXPECT_NE(slurp(run.log).find("run file " + (dir_ / "run.h5").string()), std::string::npos)
      << slurp(run.log);
  dld::H5File merged((dir_ / "run.h5").string(), dld::H5File::Mode::kRead);
  EXPECT_EQ(merged.read_attribute_number("/", "membrane_processes"), 2.0);
  for (const auto& [part, name] : std::vector<std::pair<std::string, std::string>>{
           {"run-fluid.h5", "/fluid/timeseries"},
           {"run-tracers-0.h5", "/membrane-0/tracers/samples"},
           {"run-tracers-1.h5", "/membrane-1/tracers/samples"}}) {
    dld::H5File f((dir_ / part).string(), dld::H5File::Mode::kRead);
    const std::string inside = name.substr(name.find('/', 1));
    const auto a = f.read(inside);
    EXPECT_FALSE(a.empty()) << part << inside;
    EXPECT_EQ(a, merged.read(name)) << name;
  }
}

/// Processes whose command line names `needle` (the test's own scene): the programs of a run.
std::vector<int> processes_naming(const std::string& needle) {
  std::vector<int> pids;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmd = slurp((e.path() / "cmdline").string());
    std::replace(cmd.begin(), cmd.end(), '\0', ' ');
    if (cmd.find(needle) != std::string::npos) pids.push_back(std::stoi(name));
  }
  return pids;
}

// SLURM ends a job with SIGTERM: dld-run stops every program as Ctrl-C does and writes the run
// file; killed outright (SIGKILL), it leaves no program running (the fluid ends the run).
TEST_F(TracersCoupled, LauncherStoppedBySigtermOrKilledLeavesNoProgramRunning) {
  for (const int sig : {SIGTERM, SIGKILL}) {
    const std::string sc = (dir_ / ("sig" + std::to_string(sig) + ".toml")).string();
    fs::copy_file(scene(0.8, 5.0), sc, fs::copy_options::overwrite_existing);
    {
      std::ifstream in(sc);
      std::stringstream t;
      t << in.rdbuf();
      std::string text = t.str();
      text.replace(
          text.find("[output]\n"), 9,
          "[output]\nfile = \"" + (dir_ / ("run" + std::to_string(sig) + ".h5")).string() + "\"\n");
      std::ofstream(sc) << text;
    }
    Process run = spawn({DLD_RUN_EXE, sc, "--tracers", "2", "--steps", "100000000"},
                        (dir_ / "run.log").string());
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    ASSERT_EQ(processes_naming(sc).size(), 3u) << "dld-run, dld-fluid, dld-tracers";
    kill(run.pid, sig);
    const int rc = wait_for(run, 20);
    if (sig == SIGTERM) {
      EXPECT_EQ(rc, 130) << slurp(run.log);
      EXPECT_TRUE(fs::exists(dir_ / ("run" + std::to_string(sig) + ".h5"))) << slurp(run.log);
    }
    std::vector<int> left;
    for (int t = 0; t < 100 && !(left = processes_naming(sc)).empty(); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    EXPECT_TRUE(left.empty()) << left.size() << " programs still running after signal " << sig;
    for (const int p : left) kill(p, SIGKILL);
  }
}

TEST_F(TracersCoupled, OneRedBloodCellMovesWithTheFlowAndKeepsItsVolume) {
  // dld-fluid + dld-membrane (finite-element Skalak + bending + volume, 500 faces) at dx = 0.8 um:
  // the cell starts across the periodic corner of the box, is carried downstream, stays between
  // the walls and keeps its volume (issue 4 asks < 0.5 % drift over a run).
  if (std::string(DLD_MEMBRANE_EXE).empty()) GTEST_SKIP() << "membrane part not built";
  const std::string sc = cell_scene("cell"), out = (dir_ / "cells.h5").string();
  Process fluid = spawn({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--cells", "1"},
                        (dir_ / "fluid.log").string());
  Process cell = spawn({DLD_MEMBRANE_EXE, sc, "--connect", endpoint(), "--steps", "2000",
                        "--sample-every", "500", "-o", out},
                       (dir_ / "cell.log").string());
  EXPECT_EQ(wait_for(cell, 180), 0) << slurp(cell.log);
  EXPECT_EQ(wait_for(fluid, 30), 0) << slurp(fluid.log);
  dld::H5File f(out, dld::H5File::Mode::kRead);
  std::vector<std::uint64_t> dims;
  const auto s = f.read("/cells/samples", &dims);
  ASSERT_EQ(dims[0], 5u);
  ASSERT_EQ(dims[1], 5u);
  const double* first = &s[0];
  const double* last = &s[std::size_t{4} * 5];
  EXPECT_EQ(last[0], 2000.0);
  EXPECT_GT(last[1] - first[1], 0.5) << "downstream drift [um] in 2000 steps";
  EXPECT_GT(last[3], 1.0);
  EXPECT_LT(last[3], 3.8);
  EXPECT_LT(std::abs(last[4] / first[4] - 1.0), 0.005)
      << "volume " << first[4] << " -> " << last[4];
}

TEST_F(TracersCoupled, ResumedRunEqualsAnUninterruptedOne) {
  // 600 steps straight against 300 + 300 resumed from the checkpoints dld-run writes (fluid
  // populations and controller, cell nodes and samples): the transport and restart must not change
  // the physics, so the final nodes and the trajectory agree to 1e-12.
  if (std::string(DLD_MEMBRANE_EXE).empty()) GTEST_SKIP() << "membrane part not built";
  const std::string a = cell_scene("straight"), b = cell_scene("resumed");
  run(a, {"--steps", "600"});
  run(b, {"--steps", "300"});
  run(b, {"--steps", "600", "--resume"});
  EXPECT_NE(slurp((dir_ / "resumed-cells-0.log").string()).find("at step 300"), std::string::npos);
  EXPECT_NE(slurp((dir_ / "resumed-fluid.log").string()).find("resumed from"), std::string::npos);
  EXPECT_LT(node_difference("straight", "resumed"), 1e-12);
  const auto sa = read((dir_ / "straight-cells-0.h5").string(), "/cells/samples");
  const auto sb = read((dir_ / "resumed-cells-0.h5").string(), "/cells/samples");
  ASSERT_EQ(sa.size(), sb.size()) << "the resumed trajectory has every sample once";
  for (std::size_t i = 0; i < sa.size(); ++i) EXPECT_NEAR(sa[i], sb[i], 1e-12) << i;
  dld::H5File f((dir_ / "resumed-fluid.ckpt.h5").string(), dld::H5File::Mode::kRead);
  EXPECT_EQ(f.read_attribute_number("/fluid", "step"), 600.0);
  // The fluid's time series (a row every 100 steps) is whole after the resume: the rows before
  // the checkpoint come with it (issue 18, item 6).
  const auto ta = read((dir_ / "straight-fluid.h5").string(), "/timeseries");
  const auto tb = read((dir_ / "resumed-fluid.h5").string(), "/timeseries");
  ASSERT_EQ(ta.size(), 6u * 8u);
  ASSERT_EQ(tb.size(), ta.size());
  for (std::size_t i = 0; i < ta.size(); ++i)
    EXPECT_NEAR(tb[i], ta[i], 1e-12 * (1 + std::abs(ta[i]))) << i;
  // The cell moved: the comparison is not between two resting states.
  EXPECT_GT(std::abs(sa[sa.size() - 4] - sa[1]), 0.1);
}

// Time-scale separation ([coupling] force_every, viscosity_field_every; issue 17): membrane forces
// and the viscosity field (ratio 5) updated every 2nd step move the cell differently from exact
// coupling, but by far less than it moves (0.18 % of its 0.36 lu here, 2026-12-01); a run resumed
// at an update step equals a straight one.
TEST_F(TracersCoupled, HeldForcesAndViscosityFieldStayCloseAndResumeExactly) {
  if (std::string(DLD_MEMBRANE_EXE).empty()) GTEST_SKIP() << "membrane part not built";
  const std::string ratio = "viscosity_ratio = 5.0\n";
  const std::string held = "force_every = 2\nviscosity_field_every = 2\n";
  run(cell_scene("exact", "", ratio), {"--steps", "600"});
  run(cell_scene("held", held, ratio), {"--steps", "600"});
  const std::string resumed = cell_scene("held-resumed", held, ratio);
  run(resumed, {"--steps", "300"});
  run(resumed, {"--steps", "600", "--resume"});
  EXPECT_NE(slurp((dir_ / "held-fluid.log").string()).find("membrane forces every 2 step(s)"),
            std::string::npos);
  EXPECT_LT(node_difference("held", "held-resumed"), 1e-12);
  const auto s = read((dir_ / "exact-cells-0.h5").string(), "/cells/samples");
  const double moved = std::abs(s[s.size() - 4] - s[1]) / 0.8;  // centroid x [lattice units]
  const double apart = node_difference("exact", "held");
  EXPECT_GT(apart, 0.0) << "the settings must act";
  EXPECT_LT(apart, 0.01 * moved) << "held forces moved a node by " << apart << " lu of " << moved;
}

// [coupling] spread_held and interpolation_held (issues 13 and 17): with forces and viscosity
// field held 2 steps (the scene above; 3 steps go unstable at dx 0.8 um), holding the spread force
// field, and its interpolation weights too, moves the cell differently from spreading at the moved
// nodes every step, by far less than it moves; a run resumed at an update step equals a straight
// one; with forces updated every step the keys change nothing, bit for bit.
TEST_F(TracersCoupled, HeldSpreadStaysCloseResumesExactlyAndIsInertWithoutHeldForces) {
  if (std::string(DLD_MEMBRANE_EXE).empty()) GTEST_SKIP() << "membrane part not built";
  const std::string ratio = "viscosity_ratio = 5.0\n";
  const std::string held = "force_every = 2\nviscosity_field_every = 2\n",
                    spread = "spread_held = true\n", weights = "interpolation_held = true\n";
  run(cell_scene("held2", held, ratio), {"--steps", "600"});
  const auto s = read((dir_ / "held2-cells-0.h5").string(), "/cells/samples");
  const double moved = std::abs(s[s.size() - 4] - s[1]) / 0.8;  // centroid x [lattice units]
  for (const auto& [name, keys, log] :
       {std::tuple{"spread2", spread, "(spread held with them)"},
        std::tuple{"weights2", spread + weights, "(spread and its weights held with them)"}}) {
    run(cell_scene(name, held + keys, ratio), {"--steps", "600"});
    const std::string resumed = cell_scene(std::string(name) + "-resumed", held + keys, ratio);
    run(resumed, {"--steps", "300"});
    run(resumed, {"--steps", "600", "--resume"});
    EXPECT_NE(slurp((dir_ / (std::string(name) + "-fluid.log")).string()).find(log),
              std::string::npos)
        << name;
    EXPECT_EQ(node_difference(name, std::string(name) + "-resumed"), 0.0) << name;
    const double apart = node_difference("held2", name);
    EXPECT_GT(apart, 0.0) << name << ": the setting must act";
    EXPECT_LT(apart, 0.01 * moved) << name << " moved a node by " << apart << " lu of " << moved;
  }
  run(cell_scene("exact", "", ratio), {"--steps", "300"});
  run(cell_scene("exact-spread", spread + weights, ratio), {"--steps", "300"});
  EXPECT_EQ(node_difference("exact", "exact-spread"), 0.0);
}

// A membrane program stopped (Ctrl-C, SIGTERM) while it waits for the fluid's welcome removes its
// shared-memory segment: nothing is left in /dev/shm (issue 18, item 8).
TEST_F(TracersCoupled, MembraneStoppedBeforeTheWelcomeLeavesNoSharedMemory) {
  if (std::string(DLD_MEMBRANE_EXE).empty()) GTEST_SKIP() << "membrane part not built";
  for (const int sig : {SIGINT, SIGTERM}) {
    Process cell = spawn({DLD_MEMBRANE_EXE, cell_scene("lonely"), "--connect",
                          "ipc://" + (dir_ / "nobody").string(), "--steps", "10"},
                         (dir_ / "lonely.log").string());
    const fs::path segment = "/dev/shm/dld-coupler-" + std::to_string(cell.pid) + "-0";
    for (int t = 0; t < 600 && !fs::exists(segment); ++t)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(fs::exists(segment)) << slurp(cell.log);
    kill(cell.pid, sig);
    wait_for(cell, 20);
    EXPECT_FALSE(fs::exists(segment)) << "signal " << sig << ": " << slurp(cell.log);
  }
}

}  // namespace
