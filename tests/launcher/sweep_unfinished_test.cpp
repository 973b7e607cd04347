// SPDX-License-Identifier: MIT
// dld-sweep --summary --unfinished on a study whose runs are done, partial, failed and waiting,
// with synthetic cell paths of known answers (tests/analysis/synthetic.hpp): each partial or
// failed run is analysed as it stands and listed with its state in summary-unfinished.csv; the
// finished and the waiting runs are not, nor one that has not passed a pillar (its reason
// printed); summary.csv keeps the finished runs only.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/analysis/synthetic.hpp"
#include "tests/child_process.hpp"

namespace {

namespace fs = std::filesystem;
using dld::analysis::testing::track;
using dld::analysis::testing::write_run_file;
using dld::test::slurp;
using dld::test::spawn;
using dld::test::wait_for;

class SweepUnfinished : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dld-sweep-unfinished-" + std::to_string(getpid()));
    fs::create_directories(dir_);
    std::ofstream(dir_ / "base.toml")
        << "[scene]\nname = \"base\"\n[geometry]\nrow_shift_um = 4.4\n";
    std::ofstream(dir_ / "modes.toml")
        << "[[mode]]\nrow_shift_um = 4.4\ncapillary_number = 0.5\nmode = \"displacement\"\n"
           "[[mode]]\nrow_shift_um = 6.0\ncapillary_number = 0.5\nmode = \"zigzag\"\n";
    std::ofstream(dir_ / "study.toml")
        << "[study]\nname = \"unfinished\"\nscene = \"base.toml\"\noutput = \""
        << (dir_ / "runs").string()
        << "\"\npillars = 10\nmodes = \"modes.toml\"\n[[study.axis]]\nname = \"Ht\"\n"
           "column = \"haematocrit_percent\"\nvalues = [8.0]\n[study.axis.set]\n"
           "\"cells.count\" = [2]\n[[study.axis]]\nname = \"d\"\n"
           "values = [4.4, 6.0, 2.0, 3.0, 1.0]\n[study.axis.set]\n\"geometry.row_shift_um\" = "
           "[4.4, 6.0, 2.0, 3.0, 1.0]\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path run(const std::string& name) {
    fs::path p = dir_ / "runs" / "default" / name;
    fs::create_directories(p);
    return p;
  }
  int sweep(const std::vector<std::string>& args, const std::string& log) {
    std::vector<std::string> argv{DLD_SWEEP_EXE, (dir_ / "study.toml").string()};
    argv.insert(argv.end(), args.begin(), args.end());
    auto p = spawn(argv, (dir_ / log).string());
    return wait_for(p, 120);
  }
  fs::path dir_;
};

TEST_F(SweepUnfinished, PartialAndFailedRunsAreAnalysedAsTheyStandAndListedWithTheirState) {
  // d 4.4 um, partial (a checkpoint), 6 of its 10 pillars: one cell displaced every column, one
  // going straight on (zigzag against the expected displacement: p_fD = d / lambda).
  const fs::path partial = run("Ht8-d4.4");
  std::ofstream(partial / "run-fluid.ckpt.h5") << "stand-in";
  write_run_file((partial / "run-cells-0.h5").string(),
                 {track(
                      0, 1.0, 0.0, 6.0, [](double c) { return 4.4 * c; }, 600),
                  track(
                      1, 3.0, 9.0, 6.0, [](double) { return 0.0; }, 600)},
                 {.d = 4.4, .scene = "Ht8-d4.4"});
  // d 6.0 um, failed (its last attempt's exit code 1), 3 pillars, both cells zigzag as expected.
  const fs::path failed = run("Ht8-d6");
  std::ofstream(failed / "run-fluid.ckpt.h5") << "stand-in";
  std::ofstream(failed / "attempts.csv") << "finished_unix_s,exit_code,wall_s\n1,1,3600.0\n";
  write_run_file((failed / "run-cells-0.h5").string(),
                 {track(
                      0, 1.0, 0.0, 3.0, [](double) { return 0.0; }, 300),
                  track(
                      1, 3.0, 9.0, 3.0, [](double) { return 0.0; }, 300)},
                 {.d = 6.0, .scene = "Ht8-d6"});
  // d 2.0 um, done; its own summary row stands in for its analysis. d 3.0 um, partial, has not
  // passed a pillar yet: nothing to evaluate. d 1.0 um waits.
  const fs::path done = run("Ht8-d2");
  std::ofstream(done / "done.toml") << "run = \"Ht8-d2\"\nwall_s = 10.0\n";
  std::ofstream(done / "run-summary.csv")
      << "scene_name,pillar_spacing_um,row_shift_um,capillary_number,failure,p_f_mean,p_f_std\n"
         "Ht8-d2,32,2,0.5,p_fD,0.01,0.005\n";
  const fs::path young = run("Ht8-d3");
  std::ofstream(young / "run-fluid.ckpt.h5") << "stand-in";
  write_run_file((young / "run-cells-0.h5").string(),
                 {track(
                     0, 1.0, 0.0, 0.5, [](double) { return 0.0; }, 50)},
                 {.d = 3.0, .scene = "Ht8-d3"});

  ASSERT_EQ(sweep({"--unfinished"}, "refused.log"), 2);
  EXPECT_NE(slurp((dir_ / "refused.log").string()).find("--unfinished: expected --summary too"),
            std::string::npos);
  ASSERT_EQ(sweep({"--summary", "--unfinished"}, "summary.log"), 0)
      << slurp((dir_ / "summary.log").string());
  const fs::path out = dir_ / "runs" / "default";
  EXPECT_TRUE(fs::exists(partial / "so-far" / "run-outlets.csv"));
  EXPECT_FALSE(fs::exists(partial / "run-summary.csv")) << "the run's own results stay its own";
  EXPECT_FALSE(fs::exists(run("Ht8-d1") / "so-far"));
  EXPECT_NE(slurp((dir_ / "summary.log").string())
                .find("Ht8-d3: not analysed: dld-analyze: error: " +
                      (young / "run-cells-0.h5").string() + ": no cell advanced a whole pillar"),
            std::string::npos)
      << slurp((dir_ / "summary.log").string());
  EXPECT_FALSE(fs::exists(done / "so-far"));

  const std::string table = slurp((out / "summary-unfinished.csv").string());
  ASSERT_EQ(table.rfind("run,state,haematocrit_percent,d,exact_coupling,wall_s,", 0), 0u) << table;
  const auto row = [&](const std::string& head) {
    const auto at = table.find("\n" + head);
    return at == std::string::npos ? std::string()
                                   : table.substr(at + 1, table.find('\n', at + 1) - at - 1);
  };
  const std::string d44 = row("Ht8-d4.4,partial,8,4.4,,"), d6 = row("Ht8-d6,failed,8,6,,3600.0,");
  ASSERT_FALSE(d44.empty()) << table;
  ASSERT_FALSE(d6.empty()) << table;
  EXPECT_EQ(row("Ht8-d2,"), "") << "a finished run is in summary.csv, not here";
  EXPECT_EQ(row("Ht8-d3,"), "") << "a run that passed no pillar has nothing to show";
  EXPECT_EQ(row("Ht8-d1,"), "") << "a waiting run has nothing to show";
  // Known answers: p_fD of the two cells 0 and d / lambda = 0.1375, mean 0.06875; p_fZ 0.
  EXPECT_NE(d44.find(",p_fD,0.06875"), std::string::npos) << d44;
  EXPECT_NE(d6.find(",p_fZ,0,0,"), std::string::npos) << d6;
  EXPECT_NE(d44.find(",6.000,"), std::string::npos) << "the slowest cell's pillars: " << d44;

  const std::string finished = slurp((out / "summary.csv").string());
  EXPECT_NE(finished.find("\nHt8-d2,8,2,"), std::string::npos) << finished;
  EXPECT_EQ(finished.find("\nHt8-d4.4,"), std::string::npos) << finished;
  // The plot: the finished run filled, the two unfinished ones open and named (plot_study.py's
  // lines in plots.log).
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2> /dev/null") == 0) {
    EXPECT_TRUE(fs::exists(out / "failure-probability.png")) << slurp((out / "plots.log").string());
    const std::string plots = slurp((out / "plots.log").string());
    EXPECT_NE(plots.find("unfinished: d 4.4 um, Ca 0.5, Ht 8 %: 0.0688"), std::string::npos)
        << plots;
    EXPECT_NE(plots.find("unfinished: d 6 um, Ca 0.5, Ht 8 %: 0.0000"), std::string::npos) << plots;
  }
}

}  // namespace
