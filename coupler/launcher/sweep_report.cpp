// SPDX-License-Identifier: MIT
#include "coupler/launcher/sweep_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "coupler/launcher/exact_stretches.hpp"

namespace dld::coupler {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) {
      out.push_back(line);
    }
  }
  return out;
}

/// The fields of one CSV line ("..." may hold commas).
std::vector<std::string> cells(const std::string& csv_line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (const char ch : csv_line) {
    if (ch == '"') {
      quoted = !quoted;
    } else if (ch == ',' && !quoted) {
      out.emplace_back();
    } else {
      out.back() += ch;
    }
  }
  return out;
}

/// Whether the run's last recorded attempt ended with an error (not 0, 130 or -1), and no attempt
/// has started since (attempt-running.csv: a retry under way, or killed).
bool last_attempt_failed(const StudyRun& run) {
  if (fs::exists(run.dir / "attempt-running.csv")) return false;
  const auto all = lines(run.dir / "attempts.csv");
  if (all.size() < 2) return false;  // the header only, or no file
  const auto c = cells(all.back());
  if (c.size() < 2) return false;
  const int code = std::atoi(c[1].c_str());
  return code != 0 && code != 130 && code != -1;
}
}  // namespace

std::string exact_coupling_stretches(const StudyRun& run, std::int64_t before_step) {
  std::string out;
  for (const auto& s : read_exact_stretches(exact_stretches_file((run.dir / "run").string()))) {
    if (before_step >= 0 && s.first >= before_step) continue;
    out += fmt::format("{}{}-{}", out.empty() ? "" : ";", s.first, s.last);
  }
  return out;
}

RunState run_state(const StudyRun& run) {
  if (fs::exists(run.dir / "done.toml")) {
    return RunState::kDone;
  }
  if (last_attempt_failed(run)) return RunState::kFailed;
  return has_checkpoint(run) ? RunState::kPartial : RunState::kWaiting;
}

bool has_checkpoint(const StudyRun& run) {
  return fs::exists(run.dir / "run-fluid.ckpt.h5") ||
         fs::exists(run.dir / "run-fluid.ckpt.h5.prev");
}

std::vector<const StudyRun*> runs_to_do(const std::vector<const StudyRun*>& chosen, int& done,
                                        int& failed, bool retry_failed) {
  std::vector<const StudyRun*> partial, waiting;
  done = failed = 0;
  for (const StudyRun* r : chosen) {
    switch (run_state(*r)) {
      case RunState::kDone:
        ++done;
        break;
      case RunState::kFailed:
        if (retry_failed) {
          partial.push_back(r);
        } else {
          ++failed;
        }
        break;
      case RunState::kPartial:
        partial.push_back(r);
        break;
      case RunState::kWaiting:
        waiting.push_back(r);
        break;
    }
  }
  partial.insert(partial.end(), waiting.begin(), waiting.end());
  return partial;
}

const char* state_name(RunState s) {
  switch (s) {
    case RunState::kDone:
      return "done";
    case RunState::kPartial:
      return "partial (resumes from its checkpoint)";
    case RunState::kFailed:
      return "failed (see its dld-run.failures.log; dld-sweep --retry-failed runs it again)";
    default:
      return "waiting";
  }
}

double run_wall_s(const StudyRun& run) {
  double total = 0;
  for (const auto& l : lines(run.dir / "attempts.csv")) {
    const auto c = cells(l);
    if (c.size() >= 3 && c[0] != "finished_unix_s") {
      total += std::stod(c[2]);
    }
  }
  const auto running = lines(run.dir / "attempt-running.csv");  // running, or lost to a kill
  if (running.size() >= 2) total += std::atof(running[1].c_str());
  return total;
}

namespace {

/// The "ETA S s" of a membrane progress line as a short duration ("40 s", "12 min", "3.5 h"), or
/// "" when the line has none (no pillar target, or too little progress to extrapolate).
std::string progress_eta(const std::string& line) {
  const std::size_t e = line.find("  ETA ");
  if (e == std::string::npos) return "";
  const double s = std::atof(line.c_str() + e + 6);
  if (!(s >= 0)) return "";
  if (s < 120) return fmt::format("ETA {:.0f} s", s);
  if (s < 7200) return fmt::format("ETA {:.0f} min", s / 60);
  return fmt::format("ETA {:.1f} h", s / 3600);
}

/// From a membrane progress line "... step N  pillars passed X/Y ...": N and "X/Y".
bool parse_progress(const std::string& line, long long& step, std::string& pillars) {
  const std::size_t s = line.find("] step "), p = line.find("pillars passed ");
  if (s == std::string::npos || p == std::string::npos) return false;
  try {
    step = std::stoll(line.substr(s + 7));
  } catch (const std::exception&) {
    return false;
  }
  const std::size_t from = p + 15, to = line.find(' ', from);
  pillars = line.substr(from, to == std::string::npos ? std::string::npos : to - from);
  return true;
}

}  // namespace

std::string run_progress(const StudyRun& run) {
  std::string progress;
  double slowest = 1e300;
  std::error_code ec;
  // A finished run's last progress line is from before its end: its analysis says the rest.
  const bool done = run_state(run) == RunState::kDone;
  for (const auto& e : fs::directory_iterator(run.dir, ec)) {
    if (done) break;
    const std::string f = e.path().filename().string();
    if (f.rfind("run-cells-", 0) != 0 || f.size() < 4 || f.substr(f.size() - 4) != ".log") continue;
    const auto l = lines(e.path());
    for (auto it = l.rbegin(); it != l.rend(); ++it) {
      long long s = 0;
      std::string pillars;
      if (!parse_progress(*it, s, pillars)) continue;
      const double passed = std::atof(pillars.c_str());
      if (passed < slowest) {
        slowest = passed;
        const std::string eta = progress_eta(*it);
        progress = fmt::format("step {}, {} pillars{}{}", s, pillars, eta.empty() ? "" : ", ", eta);
      }
      break;
    }
  }
  const double wall = run_wall_s(run);
  if (wall > 0)
    progress += fmt::format("{}{:.1f} h so far", progress.empty() ? "" : ", ", wall / 3600);
  const std::string exact = exact_coupling_stretches(run);
  if (!exact.empty())
    progress += fmt::format("{}exact coupling over steps {}", progress.empty() ? "" : ", ", exact);
  return progress;
}

void note_running_attempt(const StudyRun& run, double wall_s) {
  const fs::path p = run.dir / "attempt-running.csv", tmp = run.dir / "attempt-running.csv.tmp";
  std::ofstream(tmp) << fmt::format("wall_s\n{:.1f}\n", wall_s);
  std::error_code ec;
  fs::rename(tmp, p, ec);
}

void fold_lost_attempt(const StudyRun& run) {
  const fs::path p = run.dir / "attempt-running.csv";
  const auto l = lines(p);
  if (l.size() < 2) return;
  record_attempt(run, -1, std::atof(l[1].c_str()));  // removes p
}

void record_attempt(const StudyRun& run, int exit_code, double wall_s) {
  std::error_code ec;
  fs::remove(run.dir / "attempt-running.csv", ec);
  const fs::path p = run.dir / "attempts.csv";
  const bool fresh = !fs::exists(p);
  std::ofstream out(p, std::ios::app);
  if (fresh) {
    out << "finished_unix_s,exit_code,wall_s\n";
  }
  const auto now = std::chrono::system_clock::now().time_since_epoch();
  out << std::chrono::duration_cast<std::chrono::seconds>(now).count() << "," << exit_code << ","
      << fmt::format("{:.1f}", wall_s) << "\n";
}

void mark_done(const StudyRun& run, double wall_s) {
  const fs::path tmp = run.dir / "done.toml.tmp";
  std::ofstream(tmp) << fmt::format("run = \"{}\"\nwall_s = {:.1f}\n", run.name, wall_s);
  fs::rename(tmp, run.dir / "done.toml");
}

namespace {

/// A CSV field as written: quoted when it holds a comma.
std::string csv_field(const std::string& v) {
  return v.find(',') == std::string::npos ? v : "\"" + v + "\"";
}

/// The summary's table: columns in order of first appearance, one name -> value map per run. Runs
/// analysed by different versions of dld-analyze may have different columns: each value stays
/// under its own name (a column a run lacks is empty).
struct SummaryTable {
  std::vector<std::string> columns;
  std::vector<std::map<std::string, std::string>> rows;
  void add(std::map<std::string, std::string>& row, const std::string& name,
           const std::string& value) {
    if (std::find(columns.begin(), columns.end(), name) == columns.end()) columns.push_back(name);
    row[name] = value;
  }
  std::string line(const std::map<std::string, std::string>& row) const {
    std::string out;
    for (std::size_t i = 0; i < columns.size(); ++i) {
      const auto it = row.find(columns[i]);
      if (i > 0) out += ',';
      if (it != row.end()) out += csv_field(it->second);
    }
    return out;
  }
};

/// The rows of the finished runs (their <dir>/run-summary.csv) or, `unfinished`, of the partial
/// and failed ones that have an analysis of what they ran so far (<dir>/so-far/run-summary.csv,
/// under a `state` column): the axes, the wall time and dld-analyze's run summary. `missing`
/// counts the runs without one.
SummaryTable summary_table(const Study& study, const std::vector<StudyRun>& runs, bool unfinished,
                           int& missing) {
  SummaryTable t;
  std::map<std::string, std::string> none;
  t.add(none, "run", "");
  if (unfinished) t.add(none, "state", "");
  for (const auto& a : study.axes) t.add(none, a.column.empty() ? a.name : a.column, "");
  t.add(none, "exact_coupling", "");  // before wall_s: the analysis's columns follow wall_s
  t.add(none, "wall_s", "");
  const std::size_t first_axis = unfinished ? 2 : 1;
  for (const auto& run : runs) {
    const RunState state = run_state(run);
    const bool done = state == RunState::kDone;
    if (unfinished ? (done || state == RunState::kWaiting) : !done) continue;
    std::map<std::string, std::string> row{{"run", run.name}};
    if (unfinished) row["state"] = state == RunState::kFailed ? "failed" : "partial";
    for (std::size_t i = 0; i < study.axes.size(); ++i)
      row[t.columns[first_axis + i]] = fmt::format("{:g}", run.coordinates[i]);
    row["wall_s"] = fmt::format("{:.1f}", run_wall_s(run));
    const auto a =
        lines(unfinished ? so_far_dir(run) / "run-summary.csv" : run.dir / "run-summary.csv");
    if (a.size() < 2) {
      ++missing;
      if (unfinished) continue;  // nothing to show but its name: --list has that
    } else {
      const auto names = cells(a[0]), values = cells(a[1]);
      for (std::size_t i = 0; i < names.size(); ++i)
        t.add(row, names[i], i < values.size() ? values[i] : "");
    }
    // The stretches of this result: a continuation of the run (hard100-fast) adds later ones.
    const auto steps = row.find("steps");
    row["exact_coupling"] =
        exact_coupling_stretches(run, steps == row.end() ? -1 : std::atoll(steps->second.c_str()));
    t.rows.push_back(row);
  }
  return t;
}

void write_table(const fs::path& csv, const SummaryTable& t) {
  {
    std::ofstream out(csv.string() + ".tmp");
    out << fmt::format("{}", fmt::join(t.columns, ",")) << "\n";
    for (const auto& r : t.rows) out << t.line(r) << "\n";
  }
  fs::rename(csv.string() + ".tmp", csv);
}

/// On the terminal: the axes (and the state), wall time and the analysis's headline figures.
void print_table(const Study& study, const SummaryTable& t, std::size_t first_axis) {
  const auto& head = t.columns;
  std::vector<std::size_t> shown;
  for (std::size_t i = 0; i < head.size(); ++i) {
    if (i < first_axis + study.axes.size() ||
        std::string(",wall_s,failure,p_f_mean,p_f_std,O1,O2,O3,O4,slowest_cell_pillars,")
                .find("," + head[i] + ",") != std::string::npos) {
      shown.push_back(i);
    }
  }
  for (const std::size_t i : shown) {
    fmt::print("{:>12.12} ", head[i]);
  }
  fmt::print("\n");
  for (const auto& r : t.rows) {
    for (const std::size_t i : shown) {
      const auto it = r.find(head[i]);
      fmt::print("{:>12.12} ", it == r.end() ? "" : it->second);
    }
    fmt::print("\n");
  }
}

}  // namespace

fs::path so_far_dir(const StudyRun& run) {
  return run.dir / "so-far";
}

namespace {
/// <output>/<resolution>/<name>, its folder made.
fs::path summary_file(const Study& study, const std::string& resolution, const char* name) {
  const fs::path dir = study.output / (resolution.empty() ? std::string("default") : resolution);
  fs::create_directories(dir);
  return dir / name;
}
}  // namespace

std::string write_summary(const Study& study, const std::vector<StudyRun>& runs,
                          const std::string& resolution) {
  const fs::path csv = summary_file(study, resolution, "summary.csv");
  int missing = 0;
  const SummaryTable t = summary_table(study, runs, false, missing);
  write_table(csv, t);
  fmt::print("sweep summary ({} of {} runs finished{}): {}\n", t.rows.size(), runs.size(),
             missing ? fmt::format(", {} without analysis", missing) : "", csv.string());
  print_table(study, t, 1);
  return csv.string();
}

std::string write_unfinished_summary(const Study& study, const std::vector<StudyRun>& runs,
                                     const std::string& resolution) {
  const fs::path csv = summary_file(study, resolution, "summary-unfinished.csv");
  int missing = 0;
  const SummaryTable t = summary_table(study, runs, true, missing);
  if (t.rows.empty()) {
    fs::remove(csv);  // no stale rows of runs that have finished since
    return "";
  }
  write_table(csv, t);
  fmt::print(
      "unfinished runs so far (every cell over the pillars it passed; not results of the "
      "study's rule; {} of them{}): {}\n",
      t.rows.size(), missing ? fmt::format(", {} without analysis", missing) : "", csv.string());
  print_table(study, t, 2);
  return csv.string();
}

namespace {

/// What the layout adds to the script: #SBATCH lines of a task's size, lines before the run
/// (finding its hosts) and options of the run.
struct SlurmLines {
  std::string sbatch, setup, options;
};

SlurmLines slurm_lines(const SlurmLayout& l) {
  const int cpus = l.threads > 0 ? l.threads : 2;  // the fluid and the membranes take turns
  const std::string threads = l.threads > 0 ? fmt::format(" --threads {}", l.threads) : "";
  if (l.membrane_nodes <= 0)
    return {fmt::format("#SBATCH --ntasks=1\n#SBATCH --cpus-per-task={}\n", cpus), "", threads};
  const int k = l.membrane_processes > 0 ? l.membrane_processes : l.membrane_nodes;
  const int per_node = (k + l.membrane_nodes - 1) / l.membrane_nodes;
  return {fmt::format("#SBATCH --nodes={}\n#SBATCH --ntasks-per-node={}\n"
                      "#SBATCH --cpus-per-task={}\n",
                      1 + l.membrane_nodes, per_node, cpus),
          fmt::format("# The fluid on this (the first) node, {} membrane processes on the {} "
                      "others, started by dld-run through srun.\n"
                      "hosts=$(scontrol show hostnames \"$SLURM_JOB_NODELIST\" | tail -n +2 | "
                      "paste -sd, -)\n",
                      k, l.membrane_nodes),
          fmt::format(" --membrane-processes {} --hosts \"$hosts\"{}", k, threads)};
}

}  // namespace

std::string slurm_script(const Study& study, const std::string& resolution, std::size_t runs,
                         int jobs, const std::string& sweep_exe, const SlurmLayout& layout) {
  const std::string study_file = fs::absolute(study.file).string();
  const std::string res = resolution.empty() ? "" : " --resolution " + resolution;
  const SlurmLines lines = slurm_lines(layout);
  const fs::path logs = fs::absolute(study.output) / "slurm";
  return fmt::format(
      "#!/bin/bash\n"
      "# Written by dld-sweep: the study {name} ({runs} runs{resnote}) as a SLURM job array,\n"
      "# at most {jobs} runs at once. Each task runs one run of the study and resumes it from its\n"
      "# checkpoint if an earlier task was cut short (resubmit the same script: finished runs are\n"
      "# skipped). When all tasks are done:  {exe} {study} --summary{res}\n"
      "#SBATCH --job-name=dld-{name}\n"
      "#SBATCH --array=0-{last}%{jobs}\n"
      "{sbatch}"
      "#SBATCH --output={logs}/%x-%a.log\n"
      "set -euo pipefail\n"
      "mkdir -p {logs}\n"
      "cd {cwd}\n"
      "export OMP_NUM_THREADS=${{SLURM_CPUS_PER_TASK:-1}}\n"
      "{setup}"
      "exec {exe} {study} --index \"$SLURM_ARRAY_TASK_ID\"{res}{options}\n",
      fmt::arg("name", study.name), fmt::arg("runs", runs),
      fmt::arg("resnote", resolution.empty() ? "" : ", resolution " + resolution),
      fmt::arg("jobs", jobs), fmt::arg("exe", sweep_exe), fmt::arg("study", study_file),
      fmt::arg("res", res), fmt::arg("last", runs - 1), fmt::arg("logs", logs.string()),
      fmt::arg("sbatch", lines.sbatch), fmt::arg("setup", lines.setup),
      fmt::arg("options", lines.options), fmt::arg("cwd", fs::current_path().string()));
}

}  // namespace dld::coupler
