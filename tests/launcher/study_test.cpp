// SPDX-License-Identifier: MIT
// Study files (coupler/launcher/study.hpp): the runs are the Cartesian product of the axes with
// each run's scene keys set, and every kind of bad study file stops with its named error.
#include "coupler/launcher/study.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "coupler/launcher/sweep_report.hpp"
#include "shared/input_error.hpp"

namespace {

namespace fs = std::filesystem;

class StudyFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dld-study-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml") << "[scene]\nname = \"base\"\n[geometry]\nrow_shift_um = "
                                         "1.0\n[output]\nfile = \"x.h5\"\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& body) {
    const auto p = dir_ / "study.toml";
    std::ofstream(p) << "[study]\nname = \"s\"\nscene = \"base.toml\"\noutput = \""
                     << (dir_ / "out").string() << "\"\n"
                     << body;
    return p.string();
  }
  /// The InputError message of loading `body` (and listing its runs at `resolution`).
  std::string error(const std::string& body, const std::string& resolution = "") {
    try {
      (void)dld::coupler::load_study(write(body)).runs(resolution);
    } catch (const dld::InputError& e) {
      return e.what();
    }
    return "no error";
  }
  fs::path dir_;
};

const char* kTwoAxes =
    "[[study.axis]]\nname = \"Ht\"\nvalues = [8.0, 45.6]\n[study.axis.set]\n\"cells.count\" = "
    "[3, 17]\n"
    "[[study.axis]]\nname = \"d\"\nvalues = [2.0, 4.4, 6.0]\n[study.axis.set]\n"
    "\"geometry.row_shift_um\" = [2.0, 4.4, 6.0]\n\"membrane.volume.modulus_rel\" = [1.0, 2.0, "
    "3.0]\n"
    "[study.resolution.coarse]\n\"lattice.dx_um\" = 0.8\n";

TEST_F(StudyFile, RunsAreTheProductOfTheAxesWithTheirKeysSet) {
  const auto study = dld::coupler::load_study(write(kTwoAxes));
  const auto runs = study.runs("coarse");
  ASSERT_EQ(runs.size(), 6u);
  // First axis slowest.
  EXPECT_EQ(runs[0].name, "Ht8-d2");
  EXPECT_EQ(runs[5].name, "Ht45.6-d6");
  const auto& r = runs[4];  // Ht 45.6, d 4.4
  EXPECT_EQ(r.coordinates, (std::vector<double>{45.6, 4.4}));
  EXPECT_EQ(r.scene.at_path("cells.count").value<std::int64_t>(), 17);
  EXPECT_DOUBLE_EQ(*r.scene.at_path("geometry.row_shift_um").value<double>(), 4.4);
  EXPECT_DOUBLE_EQ(*r.scene.at_path("membrane.volume.modulus_rel").value<double>(), 2.0);
  EXPECT_DOUBLE_EQ(*r.scene.at_path("lattice.dx_um").value<double>(), 0.8);
  EXPECT_EQ(*r.scene.at_path("scene.name").value<std::string>(), "Ht45.6-d4.4");
  EXPECT_EQ(r.dir, dir_ / "out" / "coarse" / "Ht45.6-d4.4");
  EXPECT_EQ(*r.scene.at_path("output.file").value<std::string>(), (r.dir / "run.h5").string());
  // Without a resolution the template's own values stay.
  EXPECT_FALSE(study.runs("")[0].scene.at_path("lattice.dx_um"));
  // The written scene reads back to the same table.
  const auto back = toml::parse(dld::coupler::scene_text(r));
  EXPECT_EQ(back, r.scene);
}

// dld-sweep --slurm (issue 14): one node per run by default; with --membrane-nodes M, 1 + M
// nodes, the hosts after the first handed to every run's dld-run.
TEST_F(StudyFile, SlurmTasksSpanOneNodeOrOnePlusTheMembraneNodes) {
  const auto study = dld::coupler::load_study(write(kTwoAxes));
  const std::string one = dld::coupler::slurm_script(study, "coarse", 6, 2, "/bin/dld-sweep");
  EXPECT_NE(one.find("#SBATCH --array=0-5%2\n#SBATCH --ntasks=1\n"), std::string::npos) << one;
  EXPECT_EQ(one.find("--hosts"), std::string::npos) << one;
  const std::string three =
      dld::coupler::slurm_script(study, "coarse", 6, 2, "/bin/dld-sweep", {2, 5});
  EXPECT_NE(three.find("#SBATCH --nodes=3\n#SBATCH --ntasks-per-node=3\n"), std::string::npos)
      << three;
  EXPECT_NE(three.find("hosts=$(scontrol show hostnames \"$SLURM_JOB_NODELIST\" | tail -n +2"),
            std::string::npos)
      << three;
  EXPECT_NE(three.find("--index \"$SLURM_ARRAY_TASK_ID\" --resolution coarse "
                       "--membrane-processes 5 --hosts \"$hosts\"\n"),
            std::string::npos)
      << three;
  // The summary line names no hosts: it runs anywhere.
  EXPECT_NE(three.find("--summary --resolution coarse\n"), std::string::npos) << three;
  // dld-sweep --threads N: N cpus a task, passed on to every run.
  const std::string four =
      dld::coupler::slurm_script(study, "coarse", 6, 2, "/bin/dld-sweep", {0, 0, 4});
  EXPECT_NE(four.find("#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=4\n"), std::string::npos)
      << four;
  EXPECT_NE(four.find("--index \"$SLURM_ARRAY_TASK_ID\" --resolution coarse --threads 4\n"),
            std::string::npos)
      << four;
  EXPECT_NE(one.find("#SBATCH --cpus-per-task=2\n"), std::string::npos) << one;
  const std::string hosts =
      dld::coupler::slurm_script(study, "coarse", 6, 2, "/bin/dld-sweep", {2, 5, 4});
  EXPECT_NE(hosts.find("#SBATCH --ntasks-per-node=3\n#SBATCH --cpus-per-task=4\n"),
            std::string::npos)
      << hosts;
  EXPECT_NE(hosts.find("--membrane-processes 5 --hosts \"$hosts\" --threads 4\n"),
            std::string::npos)
      << hosts;
}

// A sweep started again resumes its partial runs before it starts waiting ones, each group in
// the order it was given (--only's), counts the done ones apart and leaves failed ones out.
TEST_F(StudyFile, PartialRunsComeFirstThenWaitingOnesInTheGivenOrder) {
  const auto runs = dld::coupler::load_study(write(kTwoAxes)).runs("coarse");
  ASSERT_EQ(runs.size(), 6u);
  std::vector<const dld::coupler::StudyRun*> chosen;
  for (const int i : {3, 5, 0, 4, 2, 1}) {
    chosen.push_back(&runs[static_cast<std::size_t>(i)]);
    fs::create_directories(runs[static_cast<std::size_t>(i)].dir);
  }
  std::ofstream(runs[1].dir / "done.toml") << "wall_s = 1\n";
  std::ofstream(runs[4].dir / "run-fluid.ckpt.h5") << "x";
  std::ofstream(runs[5].dir / "run-fluid.ckpt.h5.prev") << "x";
  int done = -1, failed = -1;
  const auto order = [&](bool retry) {
    std::vector<int> out;
    for (const auto* r : dld::coupler::runs_to_do(chosen, done, failed, retry))
      out.push_back(r->index);
    return out;
  };
  EXPECT_EQ(order(false), (std::vector<int>{5, 4, 3, 0, 2}));
  EXPECT_EQ(done, 1);
  EXPECT_EQ(failed, 0);
  // A run whose last attempt failed (the guard, exit code 1) is left out, also with a checkpoint;
  // interrupted (130) and killed (-1) attempts are not failures. --retry-failed queues it with the
  // partial ones.
  const auto attempts = [&](int run, const char* codes) {
    std::ofstream(runs[static_cast<std::size_t>(run)].dir / "attempts.csv")
        << "finished_unix_s,exit_code,wall_s\n"
        << codes;
  };
  attempts(4, "1,130,10.0\n2,1,5.0\n");
  attempts(3, "1,1,3.0\n");  // failed before its first checkpoint
  attempts(5, "1,1,3.0\n2,130,4.0\n3,-1,2.0\n");
  EXPECT_EQ(dld::coupler::run_state(runs[4]), dld::coupler::RunState::kFailed);
  EXPECT_EQ(dld::coupler::run_state(runs[5]), dld::coupler::RunState::kPartial);
  EXPECT_EQ(order(false), (std::vector<int>{5, 0, 2}));
  EXPECT_EQ(failed, 2);
  EXPECT_EQ(order(true), (std::vector<int>{3, 5, 4, 0, 2}));
  EXPECT_EQ(failed, 0);
  // Retried and under way (or killed since: the next start folds that attempt in as -1), a failed
  // run is partial again.
  std::ofstream(runs[4].dir / "attempt-running.csv") << "wall_s\n12.0\n";
  EXPECT_EQ(dld::coupler::run_state(runs[4]), dld::coupler::RunState::kPartial);
}

// --only picks runs in the order it names them (the longest first, say), --index one run; a name
// the study has not, a name given twice or an index beyond the study are one-line errors.
TEST_F(StudyFile, OnlyKeepsItsOrderAndRefusesUnknownOrRepeatedNames) {
  const auto runs = dld::coupler::load_study(write(kTwoAxes)).runs("coarse");
  const auto names = [](const std::vector<const dld::coupler::StudyRun*>& chosen) {
    std::vector<std::string> out;
    for (const auto* r : chosen) out.push_back(r->name);
    return out;
  };
  EXPECT_EQ(dld::coupler::select_runs(runs, -1, {}).size(), runs.size());
  const std::vector<std::string> some{runs[5].name, runs[0].name, runs[3].name};
  EXPECT_EQ(names(dld::coupler::select_runs(runs, -1, some)), some);
  EXPECT_EQ(names(dld::coupler::select_runs(runs, 3, some)),
            std::vector<std::string>{runs[3].name});
  const auto error = [&](int index, const std::vector<std::string>& only) -> std::string {
    try {
      (void)dld::coupler::select_runs(runs, index, only);
    } catch (const dld::InputError& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error(-1, {"Ht8-d9"}), "--only Ht8-d9: no such run (see --list)");
  EXPECT_EQ(error(-1, {runs[1].name, runs[1].name}),
            "--only " + runs[1].name + ": named twice (each run is run once)");
  EXPECT_EQ(error(6, {}), "--index 6: the study has 6 runs (0..5)");
  EXPECT_EQ(error(2, some), "--index 2 (run " + runs[2].name + "): not among --only's runs");
}

// dld-sweep --list: a partial run shows the slowest membrane process's newest progress line.
TEST_F(StudyFile, AListedPartialRunShowsItsSlowestProcessesProgress) {
  dld::coupler::StudyRun r;
  r.dir = dir_ / "run";
  fs::create_directories(r.dir);
  EXPECT_EQ(dld::coupler::run_progress(r), "");
  std::ofstream(r.dir / "run-cells-0.log")
      << "[dld-membrane] step 1000  pillars passed 0.40/2  300 steps/s  ETA 9 s  modes 0:z\n"
      << "[dld-membrane] step 2000  pillars passed 0.80/2  300 steps/s  ETA 9 s  modes 0:z\n"
      << "[dld-membrane] checkpoint written\n";
  std::ofstream(r.dir / "run-cells-1.log")
      << "[dld-membrane] step 2000  pillars passed 0.60/2  300 steps/s  ETA 9 s  modes 1:z\n";
  std::ofstream(r.dir / "run-fluid.ckpt.h5") << "x";  // partial
  EXPECT_EQ(dld::coupler::run_progress(r), "step 2000, 0.60/2 pillars, ETA 9 s");
  std::ofstream(r.dir / "attempts.csv") << "finished_unix_s,exit_code,wall_s\n1,130,5400.0\n";
  EXPECT_EQ(dld::coupler::run_progress(r), "step 2000, 0.60/2 pillars, ETA 9 s, 1.5 h so far");
  // Its membrane program's ETA as a short duration; none when the line has none.
  std::ofstream(r.dir / "run-cells-1.log")
      << "[dld-membrane] step 2000  pillars passed 0.60/2  300 steps/s  ETA 12600 s  modes 1:z\n";
  EXPECT_EQ(dld::coupler::run_progress(r), "step 2000, 0.60/2 pillars, ETA 3.5 h, 1.5 h so far");
  std::ofstream(r.dir / "run-cells-1.log")
      << "[dld-membrane] step 2000  pillars passed 0.60/2  300 steps/s  modes 1:z\n";
  EXPECT_EQ(dld::coupler::run_progress(r), "step 2000, 0.60/2 pillars, 1.5 h so far");
  // A sweep killed while the run ran left its attempt's time; the next start keeps it.
  dld::coupler::note_running_attempt(r, 1800.0);
  EXPECT_DOUBLE_EQ(dld::coupler::run_wall_s(r), 7200.0);
  dld::coupler::fold_lost_attempt(r);
  EXPECT_FALSE(fs::exists(r.dir / "attempt-running.csv"));
  EXPECT_DOUBLE_EQ(dld::coupler::run_wall_s(r), 7200.0);
  std::ifstream in(r.dir / "attempts.csv");
  const std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(all.find(",-1,1800.0\n"), std::string::npos) << all;
}

TEST_F(StudyFile, ResolutionsComeAlsoFromASharedFile) {
  std::ofstream(dir_ / "r.toml") << "[resolution.fast]\n\"drive.reynolds\" = 0.5\n";
  const auto study =
      dld::coupler::load_study(write("resolutions = \"r.toml\"\n" + std::string(kTwoAxes)));
  EXPECT_DOUBLE_EQ(*study.runs("fast")[0].scene.at_path("drive.reynolds").value<double>(), 0.5);
  EXPECT_DOUBLE_EQ(*study.runs("coarse")[0].scene.at_path("lattice.dx_um").value<double>(), 0.8);
  std::ofstream(dir_ / "r.toml") << "[resolution.coarse]\n\"drive.reynolds\" = 0.5\n";
  EXPECT_NE(
      error("resolutions = \"r.toml\"\n" + std::string(kTwoAxes)).find("'coarse': defined twice"),
      std::string::npos);
  std::ofstream(dir_ / "r.toml") << "[resolutions.fast]\n\"drive.reynolds\" = 0.5\n";
  EXPECT_NE(error("resolutions = \"r.toml\"\n" + std::string(kTwoAxes)).find("r.toml"),
            std::string::npos);
  EXPECT_NE(error("resolutions = \"none.toml\"\n" + std::string(kTwoAxes))
                .find("none.toml: no such file"),
            std::string::npos);
}

TEST_F(StudyFile, MissingKeyIsNamed) {
  EXPECT_NE(error("[[study.axis]]\nvalues = [1.0]\n[study.axis.set]\n\"a.b\" = [1]\n")
                .find("study.axis[0].name': missing"),
            std::string::npos);
}

TEST_F(StudyFile, ArrayOfWrongLengthIsNamed) {
  const auto e = error(
      "[[study.axis]]\nname = \"d\"\nvalues = [1.0, 2.0]\n[study.axis.set]\n"
      "\"geometry.row_shift_um\" = [1.0]\n");
  EXPECT_NE(e.find("geometry.row_shift_um\": expected an array of 2 values"), std::string::npos)
      << e;
}

TEST_F(StudyFile, UnknownKeyIsNamed) {
  const auto e = error(std::string(kTwoAxes) + "[study.extra]\nx = 1\n");
  EXPECT_NE(e.find("study.extra.x"), std::string::npos) << e;
}

TEST_F(StudyFile, UnknownResolutionIsNamed) {
  const auto e = error(kTwoAxes, "fine");
  EXPECT_NE(e.find("no resolution 'fine' (known: coarse)"), std::string::npos) << e;
}

TEST_F(StudyFile, RepeatedValuesAndBadNamesAreRejected) {
  EXPECT_NE(error("[[study.axis]]\nname = \"d\"\nvalues = [1.0, 1.0]\n[study.axis.set]\n\"a\" = "
                  "[1, 2]\n")
                .find("distinct"),
            std::string::npos);
  EXPECT_NE(error("[[study.axis]]\nname = \"a b\"\nvalues = [1.0]\n[study.axis.set]\n\"a\" = "
                  "[1]\n")
                .find("without spaces"),
            std::string::npos);
  EXPECT_NE(error("").find("at least one [[study.axis]]"), std::string::npos);
}

TEST_F(StudyFile, KeyThroughANonTableIsNamed) {
  const auto e = error(
      "[[study.axis]]\nname = \"d\"\nvalues = [1.0]\n[study.axis.set]\n"
      "\"geometry.row_shift_um.x\" = [1.0]\n");
  EXPECT_NE(e.find("'row_shift_um' is not a table"), std::string::npos) << e;
}

TEST_F(StudyFile, MissingTemplateIsNamed) {
  fs::remove(dir_ / "base.toml");
  const auto e = error(kTwoAxes);
  EXPECT_NE(e.find("base.toml: no such scene file"), std::string::npos) << e;
}

}  // namespace
