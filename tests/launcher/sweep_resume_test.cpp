// SPDX-License-Identifier: MIT
// dld-sweep end to end on a two-run study (one red blood cell, dx = 0.8 um, 6000 steps each): a
// sweep interrupted mid-run (Ctrl-C) and started again gives the same trajectories, to 1e-12, as
// an uninterrupted sweep (also with forces and viscosity field held between updates); finished runs
// are not run again; a changed study is refused. And dld-run --exact-coupling-for (a failed held
// coupling's retry): exact steps first, then the held coupling.
#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "shared/h5file.hpp"
#include "tests/child_process.hpp"

namespace {

namespace fs = std::filesystem;
using dld::test::slurp;
using dld::test::spawn;
using dld::test::wait_for;

class Sweep : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dld-sweep-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml")
        << "[scene]\nname = \"base\"\n[geometry]\npillar_radius_um = 10.0\n"
           "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
           "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n[run]\nthreads = 1\n"
           "[output]\nfields = false\nfile = \"x.h5\"\n[coupling]\ntimeout_s = 20\n"
           "force_every = 3\nviscosity_field_every = 2\n"
           "[membrane]\nradius_um = 3.9\nmesh_faces = 500\nmodels = [\"skalak\", \"bending\", "
           "\"volume\"]\ncapillary_number = 0.2\nmesh_cache = \""
        << (dir_ / "meshes").string()
        << "\"\n[membrane.skalak]\narea_modulus_ref_lu = 0.5\n[membrane.bending]\nmodulus_rel = "
           "2.5e-3\n[membrane.volume]\nmodulus_rel = 100.0\n[membrane.contact]\nrange_um = 0.8\n"
           "strength_rel = 1.0\n[[cells.cell]]\ncentre_um = [3.0, 3.0, 2.4]\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  /// A study of two runs (d = 4.4 and 6.0 um) writing under <dir>/<out>.
  std::string study(const std::string& out, int steps = 600) {
    const auto p = dir_ / (out + ".toml");
    std::ofstream(p) << "[study]\nname = \"" << out << "\"\nscene = \"base.toml\"\noutput = \""
                     << (dir_ / out).string() << "\"\npillars = 20\ncheckpoint_every = 200\n"
                     << "max_steps = " << steps
                     << "\n[[study.axis]]\nname = \"d\"\nvalues = [4.4, 6.0]\n"
                        "[study.axis.set]\n\"geometry.row_shift_um\" = [4.4, 6.0]\n";
    return p.string();
  }
  int sweep(const std::string& study_file, const std::string& log, double limit_s = 300) {
    auto p = spawn({DLD_SWEEP_EXE, study_file, "--jobs", "2"}, (dir_ / log).string());
    return wait_for(p, limit_s);
  }
  static std::vector<double> samples(const fs::path& run_dir) {
    dld::H5File f((run_dir / "run-cells-0.h5").string(), dld::H5File::Mode::kRead);
    return f.read("/cells/samples");
  }
  fs::path dir_;
};

TEST_F(Sweep, InterruptedSweepResumesToTheResultsOfAnUninterruptedOne) {
  // 6000 steps: after both runs' step-200 checkpoints the Ctrl-C must still find one running
  // (with 600 steps a loaded machine let both finish first: "the interruption came too late").
  constexpr int kSteps = 6000;
  ASSERT_EQ(sweep(study("straight", kSteps), "straight.log"), 0)
      << slurp((dir_ / "straight.log").string());

  const std::string resumed = study("resumed", kSteps);
  const fs::path runs = dir_ / "resumed" / "default";
  auto p = spawn({DLD_SWEEP_EXE, resumed, "--jobs", "2"}, (dir_ / "resumed-1.log").string());
  // Interrupt once both runs are under way (each wrote its step-200 checkpoint).
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(200);
  while (std::chrono::steady_clock::now() < limit &&
         !(fs::exists(runs / "d4.4" / "run-fluid.ckpt.h5") &&
           fs::exists(runs / "d6" / "run-fluid.ckpt.h5")))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(p.pid, SIGINT);
  ASSERT_EQ(wait_for(p, 120), 130) << slurp(p.log);
  EXPECT_FALSE(fs::exists(runs / "d4.4" / "done.toml") && fs::exists(runs / "d6" / "done.toml"))
      << "the interruption came too late to test anything";
  // Forces are held 3 steps and the viscosity field 2: an interrupted run ends at a multiple of 6,
  // where the resumed run recomputes what the straight one does (elsewhere they would differ).
  for (const char* run : {"d4.4", "d6"}) {
    if (fs::exists(runs / run / "done.toml")) continue;
    const auto step = [&](const char* file, const char* group) {
      const dld::H5File f((runs / run / file).string(), dld::H5File::Mode::kRead);
      return static_cast<std::int64_t>(f.read_attribute_number(group, "step"));
    };
    const std::int64_t fluid = step("run-fluid.ckpt.h5", "/fluid");
    EXPECT_EQ(fluid % 6, 0) << run << ": interrupted at step " << fluid;
    EXPECT_EQ(step("run-cells-0.ckpt.h5", "/membrane"), fluid) << run;
  }

  ASSERT_EQ(sweep(resumed, "resumed-2.log"), 0) << slurp((dir_ / "resumed-2.log").string());
  EXPECT_NE(slurp((dir_ / "resumed-2.log").string()).find("(resuming)"), std::string::npos);
  for (const char* run : {"d4.4", "d6"}) {
    const auto a = samples(dir_ / "straight" / "default" / run);
    const auto b = samples(runs / run);
    ASSERT_EQ(a.size(), b.size()) << run << ": every sample once, none lost or repeated";
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-12) << run << " " << i;
    EXPECT_GT(std::abs(a[a.size() - 4] - a[1]), 0.1) << "the cell moved";
    EXPECT_TRUE(fs::exists(runs / run / "done.toml"));
  }
  // Both runs finished: a third start runs nothing; the summary lists both.
  ASSERT_EQ(sweep(resumed, "resumed-3.log", 60), 0);
  EXPECT_NE(slurp((dir_ / "resumed-3.log").string()).find("2 done, 0 to run"), std::string::npos)
      << slurp((dir_ / "resumed-3.log").string());
  const std::string summary = slurp((runs / "summary.csv").string());
  EXPECT_NE(summary.find("\nd4.4,4.4,"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\nd6,6,"), std::string::npos) << summary;
}

TEST_F(Sweep, InterruptedWithRunsWaitingItStopsAtOnce) {
  // One run at a time: the second is still waiting when Ctrl-C comes, and the sweep must not
  // wait for it forever (it did, 2026-12-02: SLURM's SIGTERM would then burn the allocation).
  const std::string s = study("waiting", 100000);
  auto p = spawn({DLD_SWEEP_EXE, s, "--jobs", "1"}, (dir_ / "waiting.log").string());
  const fs::path first = dir_ / "waiting" / "default" / "d4.4" / "run-fluid.ckpt.h5";
  const auto limit = std::chrono::steady_clock::now() + std::chrono::seconds(200);
  while (std::chrono::steady_clock::now() < limit && !fs::exists(first))
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  kill(p.pid, SIGINT);
  EXPECT_EQ(wait_for(p, 60), 130) << slurp(p.log);
  EXPECT_NE(slurp(p.log).find("interrupted"), std::string::npos) << slurp(p.log);
}

TEST_F(Sweep, AChangedStudyIsNotResumedUnderTheOldRuns) {
  const std::string s = study("changed", 200);
  ASSERT_EQ(sweep(s, "changed-1.log"), 0) << slurp((dir_ / "changed-1.log").string());
  fs::remove(dir_ / "changed" / "default" / "d6" / "done.toml");
  std::ofstream(dir_ / "base.toml", std::ios::app)
      << "[[cells.cell]]\ncentre_um = [3.0, 20.0, 2.4]\n";
  EXPECT_EQ(sweep(s, "changed-2.log", 60), 2);
  EXPECT_NE(slurp((dir_ / "changed-2.log").string()).find("d6/scene.toml differs"),
            std::string::npos)
      << slurp((dir_ / "changed-2.log").string());
}

// dld-run --exact-coupling-for N (after a held coupling failed, e.g. Ht45.6-d6 of the headline):
// the first N steps, rounded up to the held run's exact-resume step (6 here), are those of the
// exact coupling bit for bit; then the scene's held coupling goes on from that checkpoint, and the
// stretch is recorded for the results.
TEST_F(Sweep, ExactCouplingForRunsExactStepsThenTheScenesHeldCoupling) {
  const std::string base = slurp((dir_ / "base.toml").string());
  const auto scene = [&](const std::string& name, bool exact) {
    std::string text = base;
    const auto set = [&text](const std::string& from, const std::string& to) {
      text.replace(text.find(from), from.size(), to);
    };
    set("file = \"x.h5\"", "file = \"" + (dir_ / name / "run.h5").string() + "\"");
    if (exact) {
      set("force_every = 3", "force_every = 1");
      set("viscosity_field_every = 2", "viscosity_field_every = 1");
    }
    std::ofstream(dir_ / (name + ".toml")) << text;
    return (dir_ / (name + ".toml")).string();
  };
  const auto run = [&](const std::string& name, bool exact, std::vector<std::string> extra,
                       const char* steps = "600") {
    std::vector<std::string> argv{DLD_RUN_EXE, scene(name, exact), "--membrane",
                                  "cells",     "--steps",          steps};
    argv.insert(argv.end(), extra.begin(), extra.end());
    auto p = spawn(argv, (dir_ / (name + "-" + steps + ".log")).string());
    EXPECT_EQ(wait_for(p, 300), 0) << slurp(p.log);
    return samples(dir_ / name);
  };
  const auto exact = run("exact", true, {});
  const auto held = run("held", false, {});
  const auto both = run("both", false, {"--exact-coupling-for", "200"});
  // The same stretch cut short (here by --steps; an interrupt or a failure after a checkpoint
  // likewise): the next resume finishes it at exact coupling, then goes on held, as one start.
  run("split", false, {"--exact-coupling-for", "200"}, "100");
  const auto split = run("split", false, {"--resume"});
  EXPECT_EQ(split, both) << "a stretch finished by a resume differs from one made in one start";
  EXPECT_EQ(slurp((dir_ / "split" / "run-exact-coupling.csv").string()),
            "first_step,last_step,planned_last_step\n0,100,204\n100,204,204\n");
  constexpr std::size_t kRow = 1 + 4;  // step, then x y z volume of the one cell
  ASSERT_EQ(both.size(), exact.size());
  ASSERT_EQ(both.size(), 7 * kRow) << "samples at steps 0, 100, ..., 600";
  for (std::size_t i = 0; i < 3 * kRow; ++i) EXPECT_EQ(both[i], exact[i]) << "sample value " << i;
  EXPECT_NE(both[kRow + 2], held[kRow + 2]) << "the first steps were not the held coupling's";
  double after = 0;  // from step 204 on the held coupling: no longer the exact run
  for (std::size_t i = 3 * kRow; i < both.size(); ++i) after += std::abs(both[i] - exact[i]);
  EXPECT_GT(after, 0) << "the run did not go back to the scene's held coupling";
  EXPECT_EQ(slurp((dir_ / "both" / "run-exact-coupling.csv").string()),
            "first_step,last_step,planned_last_step\n0,204,204\n");
  const std::string log = slurp((dir_ / "both-600.log").string());
  EXPECT_NE(log.find("steps 0 to 204 at exact coupling"), std::string::npos) << log;
  EXPECT_NE(log.find("resuming at step 204"), std::string::npos) << log;
}

// The programs started by hand, --exact-coupling given to the fluid only: the membrane holds its
// forces 3 steps, the fluid refuses to run them as held steps (both end non-zero, the fluid
// saying why) instead of a run that is neither coupling.
TEST_F(Sweep, AFluidToldToCoupleExactlyRefusesAMembraneThatHoldsItsForces) {
  const std::string scene = (dir_ / "base.toml").string(),
                    endpoint = "ipc://" + (dir_ / "fluid").string();
  auto fluid = spawn({DLD_FLUID_EXE, scene, "--serve", endpoint, "--peers", "1", "--cells", "1",
                      "-o", (dir_ / "f.h5").string(), "--exact-coupling"},
                     (dir_ / "fluid.log").string());
  auto membrane = spawn({DLD_MEMBRANE_EXE, scene, "--connect", endpoint, "--peer", "0", "--peers",
                         "1", "--steps", "30", "-o", (dir_ / "m.h5").string()},
                        (dir_ / "membrane.log").string());
  EXPECT_NE(wait_for(membrane, 120), 0) << slurp(membrane.log);
  EXPECT_EQ(wait_for(fluid, 60), 1) << slurp(fluid.log);
  EXPECT_NE(slurp(fluid.log).find("holds its forces 3 steps, but this fluid couples exactly"),
            std::string::npos)
      << slurp(fluid.log);
}

TEST_F(Sweep, ExactCouplingForIsRefusedWhereItCannotApply) {
  auto tracers = spawn({DLD_RUN_EXE, (dir_ / "base.toml").string(), "--membrane", "tracers",
                        "--exact-coupling-for", "100"},
                       (dir_ / "tracers.log").string());
  EXPECT_EQ(wait_for(tracers, 60), 2);
  EXPECT_NE(slurp(tracers.log).find("error: --exact-coupling-for: only runs with --membrane cells"),
            std::string::npos)
      << slurp(tracers.log);
  const std::string s = study("retry", 600);
  auto no_retry =
      spawn({DLD_SWEEP_EXE, s, "--exact-coupling-for", "100"}, (dir_ / "no-retry.log").string());
  EXPECT_EQ(wait_for(no_retry, 60), 2);
  EXPECT_NE(slurp(no_retry.log).find("--exact-coupling-for: expected --retry-failed too"),
            std::string::npos)
      << slurp(no_retry.log);
  // A failed run (its last attempt's exit code 1) is retried with the exact start; the other,
  // waiting, run starts as its setting says.
  const fs::path failed = dir_ / "retry" / "default" / "d6";
  fs::create_directories(failed);
  std::ofstream(failed / "attempts.csv") << "finished_unix_s,exit_code,wall_s\n1,1,5.0\n";
  auto dry = spawn({DLD_SWEEP_EXE, s, "--retry-failed", "--exact-coupling-for", "100", "--dry-run",
                    "--jobs", "2"},
                   (dir_ / "dry.log").string());
  ASSERT_EQ(wait_for(dry, 60), 0) << slurp(dry.log);
  const std::string log = slurp(dry.log);
  const auto line = [&](const std::string& run) {
    const std::size_t at = log.find("start " + run + " (");
    return at == std::string::npos ? std::string() : log.substr(at, log.find('\n', at) - at);
  };
  EXPECT_NE(line("d6").find("--exact-coupling-for 100"), std::string::npos) << log;
  EXPECT_EQ(line("d4.4").find("--exact-coupling-for"), std::string::npos) << log;
  EXPECT_FALSE(line("d4.4").empty()) << log;
}

}  // namespace
