// SPDX-License-Identifier: MIT
// dld-analyze: failure probabilities, modes and outlet counts of a run from its cells run files
// or the run file dld-run merges them into (docs/analysis.md, SPEC section 7). Prints a table,
// writes CSVs and, through analysis/plot_run.py, the trajectory and outlet plots.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>

#include "analysis/expected_mode.hpp"
#include "analysis/locate.hpp"
#include "analysis/pace.hpp"
#include "analysis/report.hpp"
#include "analysis/run_analysis.hpp"
#include "analysis/run_file.hpp"
#include "shared/input_error.hpp"

namespace {

using namespace dld;
using namespace dld::analysis;

constexpr const char* kPython = "/usr/bin/python3";  // Debian's, with h5py and matplotlib

struct Options {
  std::vector<std::string> files;
  std::string out_dir = ".";
  int pillars = 100;
  std::string expected_mode;
  std::string modes_file;
  bool no_plots = false;
  bool pace = false;
};

/// The command line, else the scene (stated in the run file), else the dilute-limit map: the more
/// specific source wins, and the map is not read when it would not be used.
ExpectedMode expected_mode(const Options& o, const Run& run) {
  if (!o.expected_mode.empty()) {
    return {parse_expected_mode(o.expected_mode, "--expected-mode"), "given by --expected-mode"};
  }
  if (run.expected_mode) {
    return {*run.expected_mode, "given by the scene (run file attribute /cells expected_mode)"};
  }
  std::string file = o.modes_file;
  if (file.empty()) {
    file = locate_source_file("configs/study/dilute_modes.toml", DLD_SOURCE_DIR);
    if (file.empty()) {
      return {TransportMode::kUndecided,
              "configs/study/dilute_modes.toml not found; give --expected-mode or --modes"};
    }
  }
  return lookup_expected_mode(read_dilute_modes(file), file, run.row_shift_um,
                              run.capillary_number);
}

/// Returns the plot script's exit status (0 when the PNGs were written).
int plot(const Options& o, const Run& run, const std::vector<std::string>& csvs,
         const std::string& base) {
  const std::string script = locate_source_file("analysis/plot_run.py", DLD_SOURCE_DIR);
  if (script.empty()) {
    std::fprintf(stderr, "dld-analyze: error: analysis/plot_run.py not found: no plots\n");
    return 1;
  }
  const std::filesystem::path dir(o.out_dir);
  std::vector<std::string> argv{kPython,
                                script,
                                "--cells",
                                csvs[0],
                                "--summary",
                                csvs[1],
                                "--outlets",
                                csvs[2],
                                "--trajectories-png",
                                (dir / (base + "-trajectories.png")).string(),
                                "--outlets-png",
                                (dir / (base + "-outlets.png")).string()};
  argv.insert(argv.end(), run.files.begin(), run.files.end());
  const int status = run_program(argv);
  if (status != 0) {
    std::fprintf(stderr, "dld-analyze: error: %s %s failed (exit %d): no plots\n", kPython,
                 script.c_str(), status);
  }
  return status;
}

int report_pace(const Options& o, const Run& run) {
  const RunPace p = run_pace(run);
  std::fputs(format_pace(run, p, o.pillars).c_str(), stdout);
  const std::string base = std::filesystem::path(run.stem).filename().string();
  std::printf("wrote %s\n", write_pace_csv(p, o.pillars, o.out_dir, base).c_str());
  return 0;
}

int run(int argc, char** argv) {
  CLI::App app("dld-analyze: failure probabilities and outlet counts of a run (SPEC section 7)");
  Options o;
  app.add_option("files", o.files,
                 "the run file <stem>.h5 of dld-run, or the cells run files <stem>-cells-K.h5 of "
                 "one run");
  app.add_option("-o,--output-dir", o.out_dir, "directory for the CSVs and PNGs");
  app.add_option("--pillars", o.pillars, "evaluate at N pillars (columns) from each cell's start")
      ->check(CLI::Validator(
          [](std::string& v) {
            const bool whole = !v.empty() && v.size() < 9 &&
                               v.find_first_not_of("0123456789") == std::string::npos &&
                               std::stoi(v) >= 1;
            return whole ? std::string() : "'" + v + "' is not a whole number >= 1";
          },
          "N >= 1"));
  app.add_option("--expected-mode", o.expected_mode,
                 "zigzag or displacement (default: the run file's, from the scene, else the "
                 "dilute-limit map)");
  app.add_option("--modes", o.modes_file,
                 "dilute-limit map (default: configs/study/dilute_modes.toml)");
  app.add_flag("--no-plots", o.no_plots, "CSVs only");
  app.add_flag("--pace", o.pace,
               "how far each cell got and its steps per pillar, and the step at which every cell "
               "will have passed --pillars at that pace (the stop rule); writes <base>-pace.csv, "
               "evaluates nothing");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "dld-analyze: error: %s\n", e.what());
    return 2;
  }
  try {
    if (!o.expected_mode.empty()) {
      parse_expected_mode(o.expected_mode, "--expected-mode");
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "dld-analyze: error: %s\n", e.what());
    return 2;
  }
  if (o.files.empty()) {
    std::fprintf(stderr,
                 "dld-analyze: error: no run file given: expected FILE.h5... (the run file "
                 "<stem>.h5, or the <stem>-cells-K.h5 files of one run)\n");
    return 2;
  }
  try {
    const Run run = read_run(o.files);
    if (o.pace) {
      return report_pace(o, run);
    }
    const RunAnalysis a = analyze_run(run, o.pillars, expected_mode(o, run));
    std::fputs(format_report(run, a).c_str(), stdout);
    const std::string base = std::filesystem::path(run.stem).filename().string();
    const auto csvs = write_csvs(run, a, o.out_dir, base);
    for (const auto& c : csvs) {
      std::printf("wrote %s\n", c.c_str());
    }
    std::fflush(stdout);
    if (!o.no_plots) {
      if (plot(o, run, csvs, base) != 0) {
        return 3;
      }
      std::printf("wrote %s-trajectories.png and %s-outlets.png in %s\n", base.c_str(),
                  base.c_str(), o.out_dir.c_str());
    }
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "dld-analyze: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {  // not an input error: still one line, never a crash
    std::fprintf(stderr, "dld-analyze: error: %s\n", e.what());
    return 4;
  }
}
