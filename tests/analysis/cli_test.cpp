// SPDX-License-Identifier: MIT
// The dld-analyze program on synthetic run files (CSVs, PNGs, exit codes, error lines) and
// analysis/plot_study.py on a tiny synthetic sweep.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "synthetic.hpp"

namespace dld::analysis {
namespace {

namespace fs = std::filesystem;
using testing::kLambda;
using testing::track;
using testing::write_run_file;

struct Result {
  int status;
  std::string output;  // stdout and stderr
};

Result run(const std::string& command, const std::string& dir) {
  const std::string log = dir + "/output.txt";
  const int s = std::system((command + " > " + log + " 2>&1").c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(s) ? WEXITSTATUS(s) : -1, text.str()};
}

/// The command for the run of two files, evaluated at 10 pillars against displacement.
std::string two_file_command(const std::string& dir, bool plots) {
  return std::string(DLD_ANALYZE_EXE) + " " + dir + "/run-cells-0.h5 " + dir +
         "/run-cells-1.h5 --pillars 10 --expected-mode displacement -o " + dir + "/out" +
         (plots ? "" : " --no-plots");
}

bool have_matplotlib() {
  // find_spec, not import: starting matplotlib takes seconds on a loaded machine.
  return std::system(
             "/usr/bin/python3 -c \"import importlib.util as u, sys; "
             "sys.exit(not (u.find_spec('matplotlib') and u.find_spec('h5py')))\" "
             "> /dev/null 2>&1") == 0;
}

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) {
    out.push_back(l);
  }
  return out;
}

TEST(DldAnalyze, WritesTablesAndPlotsForARunOfTwoFiles) {
  const std::string dir = testing::temp_dir("cli");
  // Two displaced cells in one file, one horizontal cell (p_fD = d / lambda) in the other.
  const double d = 4.4;
  const auto displaced = [d](double c) { return d * c + testing::wiggle(c); };
  write_run_file(
      dir + "/run-cells-0.h5",
      {track(0, 3.0, 1.0, 12.5, displaced, 600), track(1, 5.0, 8.0, 12.5, displaced, 600)},
      {.first_cell = 0, .d = d});
  write_run_file(dir + "/run-cells-1.h5",
                 {track(
                     2, 4.0, 12.0, 12.5, [](double) { return 0.0; }, 600)},
                 {.first_cell = 2, .d = d});
  const bool plots = have_matplotlib();
  const Result r = run(two_file_command(dir, plots), dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("expected mode: displacement (given by --expected-mode)"),
            std::string::npos)
      << r.output;
  const auto cells = lines(dir + "/out/run-cells.csv");
  ASSERT_EQ(cells.size(), 4u);  // header + 3 cells
  EXPECT_EQ(cells[0].rfind("cell,", 0), 0u);
  const auto summary = lines(dir + "/out/run-summary.csv");
  ASSERT_EQ(summary.size(), 2u);
  // Mean p_fD over the cells: (0 + 0 + d/lambda) / 3.
  std::stringstream row(summary[1]);
  std::vector<std::string> fields;
  for (std::string f; std::getline(row, f, ',');) {
    fields.push_back(f);
  }
  std::stringstream head(summary[0]);
  std::size_t col = 0;
  for (std::string f; std::getline(head, f, ',') && f != "p_f_mean";) {
    ++col;
  }
  ASSERT_LT(col, fields.size()) << summary[1];
  EXPECT_NEAR(std::stod(fields[col]), d / kLambda / 3, 1e-6);
  EXPECT_EQ(lines(dir + "/out/run-outlets.csv").size(), 6u);  // header, O1..O4, outside
  if (!plots) {
    GTEST_SKIP() << "/usr/bin/python3 lacks matplotlib or h5py: PNGs not checked";
  }
  EXPECT_GT(fs::file_size(dir + "/out/run-trajectories.png"), 1000u);
  EXPECT_GT(fs::file_size(dir + "/out/run-outlets.png"), 1000u);
}

TEST(DldAnalyze, PaceReportsEachCellAndTheStepOfTheStopRuleWithoutEvaluating) {
  const std::string dir = testing::temp_dir("cli-pace");
  // 600 samples 100 steps apart: cell 0 passes 0.6 columns, cell 1 0.15 (none a whole one, which
  // the evaluation refuses and the pace does not need).
  write_run_file(dir + "/run-cells-0.h5",
                 {track(
                      0, 3.0, 1.0, 0.6, [](double) { return 0.0; }, 600),
                  track(
                      1, 5.0, 8.0, 0.15, [](double) { return 0.0; }, 600)},
                 {.first_cell = 0});
  const Result r = run(std::string(DLD_ANALYZE_EXE) + " " + dir +
                           "/run-cells-0.h5 --pace --pillars 20 -o " + dir + "/out",
                       dir);
  ASSERT_EQ(r.status, 0) << r.output;
  // Cell 1: 60 000 steps for 0.15 columns, 400 000 per pillar: 20 pillars at step 8 000 000.
  EXPECT_NE(r.output.find("step 8 000 000 (cell 1 last)"), std::string::npos) << r.output;
  const auto csv = lines(dir + "/out/run-pace.csv");
  ASSERT_EQ(csv.size(), 3u);
  EXPECT_EQ(csv[2].substr(0, csv[2].rfind(',')), "1,0.1500,400000,8000000");
  EXPECT_FALSE(fs::exists(dir + "/out/run-summary.csv"));
}

TEST(DldAnalyze, TheMergedRunFileGivesTheTablesOfItsParts) {
  const std::string dir = testing::temp_dir("cli-merged");
  const double d = 4.4;
  write_run_file(dir + "/run-cells-0.h5",
                 {track(
                     0, 3.0, 1.0, 12.5, [d](double c) { return d * c; }, 300)},
                 {.first_cell = 0, .d = d});
  write_run_file(dir + "/run-cells-1.h5",
                 {track(1, 4.0, 12.0, 12.5, testing::steps, 300),
                  track(
                      2, 6.0, 20.0, 12.5, [](double) { return 0.0; }, 300)},
                 {.first_cell = 1, .d = d});
  fs::create_directories(dir + "/merged");
  testing::write_merged_run_file(dir + "/merged/run.h5",
                                 {dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"}, 2);
  const Result parts = run(two_file_command(dir, false), dir);
  ASSERT_EQ(parts.status, 0) << parts.output;
  // Plots too when they can be drawn: plot_run.py reads the cells from the run file's groups.
  const bool plots = have_matplotlib();
  const Result merged = run(std::string(DLD_ANALYZE_EXE) + " " + dir +
                                "/merged/run.h5 --pillars 10 --expected-mode displacement -o " +
                                dir + "/merged" + (plots ? "" : " --no-plots"),
                            dir);
  ASSERT_EQ(merged.status, 0) << merged.output;
  EXPECT_EQ(lines(dir + "/merged/run-cells.csv").size(), 4u);  // header + the 3 cells
  for (const char* csv : {"/run-summary.csv", "/run-cells.csv", "/run-outlets.csv"}) {
    const auto a = lines(dir + "/out" + csv);
    EXPECT_GE(a.size(), 2u) << csv;
    EXPECT_EQ(a, lines(dir + "/merged" + csv)) << csv;
  }
  if (plots) {
    EXPECT_GT(fs::file_size(dir + "/merged/run-trajectories.png"), 1000u);
  }
}

/// Column `name` of the one data row of a summary CSV (fields may be quoted, with commas inside).
std::string summary_field(const std::string& path, const std::string& name) {
  const auto split = [](const std::string& line) {
    std::vector<std::string> out(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"' && quoted && i + 1 < line.size() && line[i + 1] == '"') {
        out.back() += '"';
        ++i;
      } else if (line[i] == '"') {
        quoted = !quoted;
      } else if (line[i] == ',' && !quoted) {
        out.emplace_back();
      } else {
        out.back() += line[i];
      }
    }
    return out;
  };
  const auto rows = lines(path);
  if (rows.size() != 2) {
    return "(" + path + " has " + std::to_string(rows.size()) + " lines)";
  }
  const auto head = split(rows[0]), row = split(rows[1]);
  for (std::size_t i = 0; i < head.size() && i < row.size(); ++i) {
    if (head[i] == name) {
      return row[i];
    }
  }
  return "(no column " + name + ")";
}

TEST(DldAnalyze, ExpectedModeFromTheRunFileBeatsTheMapAndLosesToTheCommandLine) {
  const std::string dir = testing::temp_dir("cli-mode");
  // The map says displacement for this (d, Ca); the scene stated zigzag; the cell zigzags.
  std::ofstream(dir + "/map.toml") << "[[mode]]\nrow_shift_um = 4.4\ncapillary_number = 0.5\n"
                                      "mode = \"displacement\"\nsource = \"test map\"\n";
  const auto zigzag = [](double c) { return testing::wiggle(c); };
  write_run_file(dir + "/map-cells-0.h5", {track(0, 3.0, 1.0, 12.5, zigzag, 600)}, {});
  write_run_file(dir + "/scene-cells-0.h5", {track(0, 3.0, 1.0, 12.5, zigzag, 600)},
                 {.expected_mode = "zigzag"});
  const auto analyze = [&](const std::string& name, const std::string& args) {
    const Result r = run(std::string(DLD_ANALYZE_EXE) + " " + dir + "/" + name +
                             "-cells-0.h5 --pillars 10 --no-plots --modes " + dir + "/map.toml " +
                             args + " -o " + dir + "/" + name,
                         dir);
    EXPECT_EQ(r.status, 0) << r.output;
    return r.output;
  };
  const auto summary = [&](const std::string& name, const std::string& column) {
    return summary_field(dir + "/" + name + "/" + name + "-summary.csv", column);
  };
  // Without the attribute the map decides: it really disagrees with the scene below.
  std::string out = analyze("map", "");
  EXPECT_NE(out.find("expected mode: displacement (" + dir + "/map.toml"), std::string::npos)
      << out;
  EXPECT_EQ(summary("map", "expected_mode"), "displacement");
  // The scene's attribute wins over the map, in the terminal and in the summary.
  const std::string scene = "given by the scene (run file attribute /cells expected_mode)";
  out = analyze("scene", "");
  EXPECT_NE(out.find("expected mode: zigzag (" + scene + ")"), std::string::npos) << out;
  EXPECT_EQ(summary("scene", "expected_mode"), "zigzag");
  EXPECT_EQ(summary("scene", "expected_source"), scene);
  EXPECT_EQ(summary("scene", "failure"), "p_fZ");
  EXPECT_NEAR(std::stod(summary("scene", "p_f_mean")), 0.0, 1e-9);  // an ideal zigzag cell
  // The command line wins over the attribute.
  out = analyze("scene", "--expected-mode displacement");
  EXPECT_NE(out.find("expected mode: displacement (given by --expected-mode)"), std::string::npos)
      << out;
  EXPECT_EQ(summary("scene", "expected_mode"), "displacement");
  EXPECT_EQ(summary("scene", "expected_source"), "given by --expected-mode");
}

TEST(DldAnalyze, BadInputIsOneErrorLineAndANonZeroExit) {
  const std::string dir = testing::temp_dir("cli-bad");
  write_run_file(dir + "/ok-cells-0.h5",
                 {track(
                     0, 3.0, 1.0, 3.5, [](double c) { return testing::wiggle(c); }, 100)},
                 {});
  const std::string exe = DLD_ANALYZE_EXE;
  const auto expect_error = [&](const std::string& args, const std::string& words) {
    const Result r = run(exe + " " + args + " --no-plots -o " + dir, dir);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.output.find("dld-analyze: error: "), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(words), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;  // one line
  };
  expect_error(dir + "/none-cells-0.h5", dir + "/none-cells-0.h5: no such file");
  expect_error(dir + "/ok-cells-0.h5 --pillars 0", "--pillars");
  expect_error(dir + "/ok-cells-0.h5 --pillars many", "--pillars");
  expect_error(dir + "/ok-cells-0.h5 --expected-mode sideways", "--expected-mode");
  expect_error(dir + "/ok-cells-0.h5 --modes " + dir + "/nomap.toml", "nomap.toml");
  expect_error("", "no run file given");
  expect_error(dir + "/ok-cells-0.h5 --pillars 2.5", "--pillars: '2.5' is not a whole number");
  write_run_file(dir + "/mode-cells-0.h5",
                 {track(
                     0, 3.0, 1.0, 3.5, [](double c) { return testing::wiggle(c); }, 100)},
                 {.expected_mode = "sideways"});
  expect_error(dir + "/mode-cells-0.h5",
               dir + "/mode-cells-0.h5: /cells expected_mode: 'sideways' is not a mode");
}

TEST(PlotStudy, DrawsFailureAgainstHaematocritFromSummaries) {
  if (!have_matplotlib()) {
    GTEST_SKIP() << "/usr/bin/python3 lacks matplotlib";
  }
  const std::string dir = testing::temp_dir("study");
  std::ofstream(dir + "/study.csv")
      << "haematocrit_percent,row_shift_um,capillary_number,p_f_mean,p_f_std,pillar_spacing_um\n"
         "8.0,4.4,0.2,0.01,0.005,32\n16.1,4.4,0.2,0.03,0.01,32\n8.0,6.0,0.5,0.02,,32\n"
         "16.1,6.0,0.5,,,32\n";
  const Result r = run("/usr/bin/python3 " DLD_SOURCE_DIR "/analysis/plot_study.py " + dir +
                           "/study.csv -o " + dir + "/study.png",
                       dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(dir + "/study.png"), 1000u);
  std::ofstream(dir + "/bad.csv") << "row_shift_um,p_f_mean\n4.4,0.1\n";
  const Result bad = run("/usr/bin/python3 " DLD_SOURCE_DIR "/analysis/plot_study.py " + dir +
                             "/bad.csv -o " + dir + "/bad.png",
                         dir);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("missing column(s) haematocrit_percent"), std::string::npos)
      << bad.output;
}

TEST(PlotStudy, DrawsUnfinishedRunsAsFarAsTheyGotBesideTheFinishedOnes) {
  if (!have_matplotlib()) {
    GTEST_SKIP() << "/usr/bin/python3 lacks matplotlib";
  }
  const std::string dir = testing::temp_dir("study-unfinished");
  const std::string head =
      "haematocrit_percent,row_shift_um,capillary_number,p_f_mean,p_f_std,pillar_spacing_um";
  // No finished run has a failure probability yet: the unfinished ones alone make the plot.
  std::ofstream(dir + "/done.csv") << head << "\n8.0,4.4,0.2,,,32\n";
  // Nor one that has no row at all (dld-sweep's summary before a run has finished: no columns of
  // the analysis either).
  std::ofstream(dir + "/none.csv") << "run,d,exact_coupling,wall_s\n";
  std::ofstream(dir + "/so-far.csv")
      << "state," << head << ",slowest_cell_pillars\nfailed,32.2,4.4,0.2,0.103,0.03,32,18.671\n"
      << "partial,45.6,6.0,1.0,0.004,0.055,32,3.26\npartial,40.2,6.0,1.0,,,32,0.4\n";
  const std::string plot = "/usr/bin/python3 " DLD_SOURCE_DIR "/analysis/plot_study.py " + dir;
  const Result r =
      run(plot + "/done.csv -o " + dir + "/study.png --unfinished " + dir + "/so-far.csv", dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(dir + "/study.png"), 1000u);
  EXPECT_NE(r.output.find("unfinished: d 4.4 um, Ca 0.2, Ht 32.2 %: 0.1030 +- 0.0300 (failed, "
                          "slowest cell 18.7 pillars)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("Ht 45.6 %: 0.0040 +- 0.0550 (partial, slowest cell 3.3 pillars)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("Ht 40.2"), std::string::npos) << "no failure probability, no point";
  const Result alone =
      run(plot + "/none.csv -o " + dir + "/alone.png --unfinished " + dir + "/so-far.csv", dir);
  ASSERT_EQ(alone.status, 0) << alone.output;
  EXPECT_NE(alone.output.find("Ht 32.2 %: 0.1030"), std::string::npos) << alone.output;
  std::ofstream(dir + "/stateless.csv") << head << "\n32.2,4.4,0.2,0.1,0.03,32\n";
  const Result bad =
      run(plot + "/done.csv -o " + dir + "/bad.png --unfinished " + dir + "/stateless.csv", dir);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("stateless.csv: missing column state"), std::string::npos)
      << bad.output;
}

TEST(PlotVolumeDrift, GivesTheSmallestAndTheMeanVolumeChangeOverEveryPart) {
  if (!have_matplotlib()) {
    GTEST_SKIP() << "/usr/bin/python3 lacks matplotlib";
  }
  const std::string dir = testing::temp_dir("volume-drift");
  // Two parts: cell 0 loses 4 % linearly, cells 1 and 2 keep their volume.
  auto shrinking = testing::track(0, 3.0, 1.0, 1.0, testing::steps, 10);
  for (std::size_t i = 0; i < shrinking.volume.size(); ++i) {
    shrinking.volume[i] = 94.0 * (1.0 - 0.004 * static_cast<double>(i));
  }
  testing::write_run_file(dir + "/a-cells-0.h5", {shrinking}, {.first_cell = 0});
  testing::write_run_file(dir + "/a-cells-1.h5",
                          {testing::track(1, 4.0, 12.0, 1.0, testing::steps, 10),
                           testing::track(2, 6.0, 20.0, 1.0, testing::steps, 10)},
                          {.first_cell = 1});
  testing::write_merged_run_file(dir + "/a.h5", {dir + "/a-cells-0.h5", dir + "/a-cells-1.h5"}, 2);
  const std::string script = "/usr/bin/python3 " DLD_SOURCE_DIR "/analysis/plot_volume_drift.py ";
  const Result r =
      run(script + dir + "/drift.png 'run a=" + dir + "/a.h5' --csv " + dir + "/drift.csv", dir);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(dir + "/drift.png"), 1000u);
  const auto rows = lines(dir + "/drift.csv");
  ASSERT_EQ(rows.size(), 12u);  // header + 11 samples
  // Last sample: step 1000, t = 1000 x 1e-7 s = 0.1 ms; smallest -4 %, mean -4/3 %.
  EXPECT_EQ(rows.back(), "run a,1000,0.1,-4,-1.3333") << rows.back();
  // A running run's membrane part file (run-cells-k.h5, every sample so far) reads alike.
  const Result part = run(
      script + dir + "/part.png 'part=" + dir + "/a-cells-0.h5' --csv " + dir + "/part.csv", dir);
  ASSERT_EQ(part.status, 0) << part.output;
  EXPECT_EQ(lines(dir + "/part.csv").back(), "part,1000,0.1,-4,-4") << part.output;
  const Result bad = run(script + dir + "/bad.png " + dir + "/a.h5", dir);
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("expected LABEL=run.h5"), std::string::npos) << bad.output;
  const Result missing = run(script + dir + "/bad.png x=" + dir + "/none.h5", dir);
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.output.find("none.h5: cannot open as HDF5"), std::string::npos)
      << missing.output;
}

}  // namespace
}  // namespace dld::analysis
