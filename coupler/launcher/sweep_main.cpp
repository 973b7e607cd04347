// SPDX-License-Identifier: MIT
// dld-sweep: the runs of a study file (configs/study/study.toml: 5 Ht x 3 d x 3 Ca), K at a
// time, each through dld-run until every cell has passed the study's pillars, then dld-analyze on
// it; a summary table and the study's plots at the end. Resumable: finished runs (done.toml) are
// skipped, interrupted ones continue from their last checkpoint (dld-run --resume), so no result
// is lost or counted twice. Ctrl-C stops every running run with a checkpoint.
#include <fmt/format.h>
#include <signal.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include "coupler/launcher/exact_stretches.hpp"
#include "coupler/launcher/process.hpp"
#include "coupler/launcher/study.hpp"
#include "coupler/launcher/sweep_report.hpp"
#include "shared/guarded_main.hpp"
#include "shared/input_error.hpp"

namespace {

namespace fs = std::filesystem;
using dld::coupler::StudyRun;

volatile sig_atomic_t g_interrupted = 0;
void on_sigint(int) {
  g_interrupted = 1;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes the run's scene once; later starts check that the study still gives the same scene, so
/// a resumed run never continues under changed physics.
fs::path prepare(const StudyRun& run) {
  fs::create_directories(run.dir);
  fs::path scene = run.dir / "scene.toml";
  const std::string text = dld::coupler::scene_text(run);
  if (fs::exists(scene)) {
    if (slurp(scene) != text) {
      throw dld::InputError(fmt::format(
          "run {}: {} differs from the scene the study gives now (study or template changed); "
          "move {} away to run it afresh",
          run.name, scene.string(), run.dir.string()));
    }
  } else {
    std::ofstream(scene.string() + ".tmp") << text;
    fs::rename(scene.string() + ".tmp", scene);
  }
  return scene;
}

struct Running {
  const StudyRun* run;
  dld::coupler::Child child;
  std::chrono::steady_clock::time_point start;
  bool exact_start = false;        ///< started with dld-run --exact-coupling-for
  std::size_t stretches_before{};  ///< its exact-coupling stretches when it started
};

/// The stretches a run has run at exact coupling (rows of <dir>/run-exact-coupling.csv).
std::size_t exact_stretch_count(const StudyRun& run) {
  return dld::coupler::read_exact_stretches(
             dld::coupler::exact_stretches_file((run.dir / "run").string()))
      .size();
}

/// A failed attempt's log is kept (the next attempt rewrites dld-run.log): appended to
/// <dir>/dld-run.failures.log under a line with the exit code.
void keep_failure_log(const StudyRun& run, int exit_code) {
  std::ofstream out(run.dir / "dld-run.failures.log", std::ios::app);
  out << fmt::format("==== attempt ended with exit code {} ({} s since the epoch)\n", exit_code,
                     std::chrono::duration_cast<std::chrono::seconds>(
                         std::chrono::system_clock::now().time_since_epoch())
                         .count())
      << slurp(run.dir / "dld-run.log");
}

/// The membrane part files dld-run writes (run-cells-K.h5), in the run's directory.
std::vector<std::string> part_files(const StudyRun& run) {
  std::vector<std::string> parts;
  for (const auto& e : fs::directory_iterator(run.dir)) {
    const std::string f = e.path().filename().string();
    if (f.rfind("run-cells-", 0) == 0 && f.size() > 3 && f.substr(f.size() - 3) == ".h5" &&
        f.find(".ckpt") == std::string::npos) {
      parts.push_back(e.path().string());
    }
  }
  std::sort(parts.begin(), parts.end());
  return parts;
}

/// dld-analyze on a finished run (its CSVs and plots go into the run's directory): on the run file
/// dld-run wrote, else (dld-run could not merge; it said why in the run's log) on the part files,
/// which give the same results. `so_far`: on an unfinished run as it stands, into so_far_dir,
/// from its part files (a run file there may be an older attempt's merge).
int analyze(const StudyRun& run, const dld::coupler::Study& study, const std::string& exe,
            bool so_far = false) {
  std::vector<std::string> argv{exe};
  const fs::path out = so_far ? dld::coupler::so_far_dir(run) : run.dir;
  const std::vector<std::string> parts = part_files(run);
  if (fs::is_regular_file(run.dir / "run.h5") && (!so_far || parts.empty())) {
    argv.push_back((run.dir / "run.h5").string());
  } else {
    argv.insert(argv.end(), parts.begin(), parts.end());
  }
  if (so_far) fs::remove_all(out);  // no earlier analysis may pass for this one
  if (argv.size() == 1) return -1;  // nothing written yet
  fs::create_directories(out);
  argv.insert(argv.end(), {"--pillars", std::to_string(study.pillars), "-o", out.string()});
  if (!study.modes.empty()) {
    argv.insert(argv.end(), {"--modes", study.modes.string()});
  }
  auto c = dld::coupler::start_child("dld-analyze", argv, (out / "analysis.txt").string());
  return dld::coupler::wait_child(c);
}

/// As many runs at a time as the cores hold at --threads or the runs' [run] threads (0 = every
/// core: one). Runs side by side at one thread each gave more steps per second in all than one run
/// on every core (2-core machine, 2026-12-01: 17 cells 1.17-1.19x, 3 cells 1.34-1.40x), about as
/// many since dld-run's short OpenMP spin (2026-12-07; docs/performance.md).
int default_jobs(const std::deque<const StudyRun*>& queue, int threads_option) {
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  if (queue.empty()) return 1;
  const auto t = threads_option > 0
                     ? std::int64_t{threads_option}
                     : queue.front()->scene["run"]["threads"].value_or(std::int64_t{0});
  const int threads = t > 0 ? static_cast<int>(t) : cores;
  return std::clamp(cores / threads, 1, static_cast<int>(queue.size()));
}

struct Options {
  std::string study_path, resolution, slurm;
  int jobs = 0, index = -1;          // jobs 0: one run per core, see default_jobs
  dld::coupler::SlurmLayout layout;  ///< --membrane-nodes, --membrane-processes
  std::vector<std::string> hosts;
  std::vector<std::string> only;
  bool list = false, summary_only = false, unfinished = false, dry = false, retry_failed = false;
  std::int64_t exact_coupling_for = 0;  ///< with retry_failed: dld-run --exact-coupling-for
};

void add_options(CLI::App& app, Options& o) {
  app.add_option("study", o.study_path, "study file (TOML), e.g. configs/study/study.toml")
      ->required();
  app.add_option("--resolution", o.resolution,
                 "a [study.resolution.NAME] of the study file (coarser lattice and mesh)");
  app.add_option("--jobs,-j", o.jobs,
                 "runs at the same time (default: cores / --threads or the runs' [run] threads)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--index", o.index, "run only the run with this index (0-based; SLURM arrays)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--only", o.only,
                 "run only the runs with these names, in this order (see --list)");
  app.add_flag("--list", o.list, "list the runs and their state, run nothing");
  app.add_flag("--retry-failed", o.retry_failed,
               "run again the runs whose last attempt failed (left out otherwise: a resume "
               "repeats the same steps and fails the same way)");
  app.add_option("--exact-coupling-for", o.exact_coupling_for,
                 "with --retry-failed: a failed run starts again with its next STEPS steps at "
                 "exact coupling, then its setting's (dld-run --exact-coupling-for; for a held "
                 "coupling that failed where the exact one holds); a run that fails during the "
                 "sweep is retried so at once, while each retry gets past its exact steps")
      ->check(CLI::PositiveNumber);
  app.add_flag("--summary", o.summary_only, "only collect the summary table and plots");
  app.add_flag("--unfinished", o.unfinished,
               "with --summary: also analyse each partial or failed run as it stands (each cell "
               "over the pillars it passed; into RUN/so-far), in summary-unfinished.csv and as "
               "open markers in the plot");
  app.add_option("--slurm", o.slurm, "write a SLURM job-array script to this file, run nothing");
  app.add_flag("--dry-run", o.dry, "write the run scenes and print the commands, start nothing");
  app.add_option("--membrane-processes", o.layout.membrane_processes,
                 "each run's membrane processes (dld-run --membrane-processes)")
      ->check(CLI::Range(1, 64));
  app.add_option("--threads", o.layout.threads,
                 "each run's OpenMP threads per program (dld-run --threads; default: the "
                 "setting's [run] threads; round-off only); with --slurm also a task's cpus")
      ->check(CLI::Range(1, 1024));
  app.add_option("--hosts", o.hosts, "each run's membrane hosts, comma-separated (dld-run --hosts)")
      ->delimiter(',');
  app.add_option("--membrane-nodes", o.layout.membrane_nodes,
                 "with --slurm: 1 + M nodes per run, the fluid on one, membrane processes on M")
      ->check(CLI::Range(1, 64));
}

/// What every run's dld-run gets beside the sweep's own options.
std::vector<std::string> placement_args(const Options& o) {
  std::vector<std::string> a;
  if (o.layout.membrane_processes > 0)
    a.insert(a.end(), {"--membrane-processes", std::to_string(o.layout.membrane_processes)});
  if (o.layout.threads > 0) a.insert(a.end(), {"--threads", std::to_string(o.layout.threads)});
  if (!o.hosts.empty()) a.insert(a.end(), {"--hosts", fmt::format("{}", fmt::join(o.hosts, ","))});
  return a;
}

/// Each partial or failed run analysed as it stands (dld-analyze into so_far_dir), then the rows
/// of those that have an analysis in summary-unfinished.csv; its path, or "" if none.
std::string write_unfinished(const dld::coupler::Study& study, const std::vector<StudyRun>& runs,
                             const std::string& resolution) {
  std::string exe;
  try {
    exe = dld::coupler::find_program("dld-analyze", DLD_ANALYZE_EXE);
  } catch (const dld::InputError&) {
    fmt::print(stderr, "dld-sweep: dld-analyze not built: unfinished runs are not analysed\n");
    return "";
  }
  setenv("HDF5_USE_FILE_LOCKING", "FALSE", 0);  // a running run's part files are open for writing
  for (const auto& run : runs) {
    const auto state = dld::coupler::run_state(run);
    if (state != dld::coupler::RunState::kPartial && state != dld::coupler::RunState::kFailed)
      continue;
    // A run that passed no pillar yet is refused by dld-analyze ("nothing to evaluate"): its line.
    if (analyze(run, study, exe, true) > 0) {
      fmt::print(
          stderr, "  {}: not analysed: {}\n", run.name,
          dld::coupler::error_line((dld::coupler::so_far_dir(run) / "analysis.txt").string()));
    }
  }
  return dld::coupler::write_unfinished_summary(study, runs, resolution);
}

/// The summary table of the whole study and its failure-probability plot; `unfinished`: with the
/// partial and failed runs as they stand, as open markers.
void write_study_summary(const dld::coupler::Study& study, const std::vector<StudyRun>& runs,
                         const std::string& resolution, bool unfinished = false) {
  const std::string csv = dld::coupler::write_summary(study, runs, resolution);
  const std::string so_far = unfinished ? write_unfinished(study, runs, resolution) : "";
  const fs::path plot = fs::path(DLD_SOURCE_DIR) / "analysis" / "plot_study.py";
  if (!fs::exists(plot) || !fs::exists("/usr/bin/python3")) return;
  const std::string png = (fs::path(csv).parent_path() / "failure-probability.png").string();
  std::vector<std::string> p{"/usr/bin/python3", plot.string(), csv, "-o", png};
  if (!so_far.empty()) p.insert(p.end(), {"--unfinished", so_far});
  auto c = dld::coupler::start_child("plot_study", p,
                                     (fs::path(csv).parent_path() / "plots.log").string());
  if (dld::coupler::wait_child(c) != 0) {
    fmt::print(stderr, "dld-sweep: no plot: {}\n", dld::coupler::error_line(c.log));
  } else {
    fmt::print("plot: {} (trajectories and outlets: each run's directory{})\n", png,
               so_far.empty() ? "" : "; as they stand: RUN/so-far");
  }
}

/// The runs still to do, K at a time: each is started (resumed when partial), watched, analysed
/// when it ends, and reported every 10 s.
class Sweep {
 public:
  Sweep(const dld::coupler::Study& study, std::deque<const StudyRun*> queue, int jobs, bool dry,
        int done_before, std::vector<std::string> run_args, std::int64_t exact_for_failed)
      : study_(study),
        queue_(std::move(queue)),
        jobs_(jobs),
        dry_(dry),
        done_before_(done_before),
        run_args_(std::move(run_args)),
        exact_for_failed_(exact_for_failed) {
    run_exe_ = dld::coupler::find_program("dld-run", DLD_RUN_EXE);
    try {
      analyze_exe_ = dld::coupler::find_program("dld-analyze", DLD_ANALYZE_EXE);
    } catch (const dld::InputError&) {
      fmt::print(stderr, "dld-sweep: dld-analyze not built: runs are not analysed\n");
    }
  }
  /// Runs everything; the names of the runs that failed.
  std::vector<std::string> run() {
    t0_ = last_report_ = std::chrono::steady_clock::now();
    // Interrupted: no new run starts, so the sweep ends once the running ones have stopped.
    while ((!queue_.empty() && !g_interrupted) || !running_.empty()) {
      start_ready();
      if (dry_) break;
      if (g_interrupted)
        for (auto& x : running_) dld::coupler::signal_child(x.child, SIGINT);
      reap();
      report();
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return failed_;
  }

 private:
  void start_ready() {
    while (!g_interrupted && !queue_.empty() && static_cast<int>(running_.size()) < jobs_) {
      const StudyRun* r = queue_.front();
      queue_.pop_front();
      const fs::path scene = prepare(*r);
      const bool retried = dld::coupler::run_state(*r) == dld::coupler::RunState::kFailed;
      if (!dry_) dld::coupler::fold_lost_attempt(*r);  // a killed sweep's attempt, before this one
      const bool resume = dld::coupler::has_checkpoint(*r);  // partial, or failed and retried
      const std::int64_t steps = study_.max_steps > 0 ? study_.max_steps : 1000000000000LL;
      std::vector<std::string> cmd{run_exe_,
                                   scene.string(),
                                   "--membrane",
                                   "cells",
                                   "--pillars",
                                   std::to_string(study_.pillars),
                                   "--steps",
                                   std::to_string(steps),
                                   "--checkpoint-every",
                                   std::to_string(study_.checkpoint_every)};
      if (resume) cmd.push_back("--resume");
      if (retried && exact_for_failed_ > 0)
        cmd.insert(cmd.end(), {"--exact-coupling-for", std::to_string(exact_for_failed_)});
      cmd.insert(cmd.end(), run_args_.begin(), run_args_.end());
      fmt::print("  start {} ({}): {}\n", r->name, resume ? "resuming" : "new",
                 fmt::join(cmd, " "));
      if (dry_) continue;
      const std::size_t stretches = exact_stretch_count(*r);  // before the run can add one
      running_.push_back(
          {r, dld::coupler::start_child(r->name, cmd, (r->dir / "dld-run.log").string(), SIGTERM),
           std::chrono::steady_clock::now(), retried && exact_for_failed_ > 0, stretches});
    }
  }

  void reap() {
    for (auto it = running_.begin(); it != running_.end();) {
      if (!dld::coupler::poll_child(it->child)) {
        ++it;
        continue;
      }
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - it->start).count();
      dld::coupler::record_attempt(*it->run, it->child.exit_code, wall);
      if (it->child.exit_code == 0) {
        const int a = analyze_exe_.empty() ? -2 : analyze(*it->run, study_, analyze_exe_);
        if (a == -1) fmt::print(stderr, "  {}: no run file to analyse\n", it->run->name);
        if (a > 0) {
          fmt::print(stderr, "  {}: dld-analyze failed ({}): see {}\n", it->run->name, a,
                     (it->run->dir / "analysis.txt").string());
        }
        dld::coupler::mark_done(*it->run, dld::coupler::run_wall_s(*it->run));
        ++finished_;
        fmt::print("  done {} in {:.0f} s\n", it->run->name, wall);
      } else if (!g_interrupted) {
        fmt::print(stderr, "  {} failed (exit {}): {}\n", it->run->name, it->child.exit_code,
                   dld::coupler::error_line(it->child.log));
        keep_failure_log(*it->run, it->child.exit_code);
        if (retry(*it)) {
          queue_.push_front(it->run);
          fmt::print(stderr, "  {}: retried from its last checkpoint, {} steps at exact coupling\n",
                     it->run->name, exact_for_failed_);
        } else {
          failed_.push_back(it->run->name);
        }
      }
      it = running_.erase(it);
    }
  }

  /// With --exact-coupling-for, a run that fails is retried at once from its checkpoint, its
  /// first steps at exact coupling, as long as every retry gets somewhere: not when the exact
  /// steps failed before their first checkpoint (no new stretch), and at most kMaxRetries times
  /// per sweep.
  bool retry(const Running& r) {
    static constexpr int kMaxRetries = 10;
    if (r.child.exit_code == 130) return false;  // stopped from outside: no failure
    if (exact_for_failed_ == 0 || retries_[r.run->name] >= kMaxRetries) return false;
    if (r.exact_start && exact_stretch_count(*r.run) <= r.stretches_before) return false;
    ++retries_[r.run->name];
    return true;
  }

  void report() {
    const auto now = std::chrono::steady_clock::now();
    if (now - last_report_ <= std::chrono::seconds(10) || running_.empty()) return;
    fmt::print("[{:.0f} s] sweep: {} done, {} running, {} waiting, {} failed\n",
               std::chrono::duration<double>(now - t0_).count(), done_before_ + finished_,
               running_.size(), queue_.size(), failed_.size());
    for (const auto& x : running_) {
      fmt::print("  {}: {}\n", x.run->name,
                 dld::coupler::last_line((x.run->dir / "run-cells-0.log").string()));
      dld::coupler::note_running_attempt(*x.run,
                                         std::chrono::duration<double>(now - x.start).count());
    }
    std::fflush(stdout);
    last_report_ = now;
  }

  const dld::coupler::Study& study_;
  std::deque<const StudyRun*> queue_;
  const int jobs_;
  const bool dry_;
  const int done_before_;
  const std::vector<std::string> run_args_;  ///< placement: --membrane-processes, --hosts
  const std::int64_t exact_for_failed_;      ///< a retried failed run's exact steps (0: none)
  std::string run_exe_, analyze_exe_;
  std::vector<Running> running_;
  std::vector<std::string> failed_;
  std::map<std::string, int> retries_;  ///< retries of each run in this sweep
  int finished_ = 0;
  std::chrono::steady_clock::time_point t0_, last_report_;
};

}  // namespace

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-sweep: the runs of a study file, K at a time, resumable"};
  Options o;
  add_options(app, o);
  CLI11_PARSE(app, argc, argv);
  try {
    const auto study = dld::coupler::load_study(o.study_path);
    const std::string resolution = o.resolution.empty() ? study.default_resolution : o.resolution;
    const auto runs = study.runs(resolution);
    const std::vector<const StudyRun*> chosen = dld::coupler::select_runs(runs, o.index, o.only);
    if (o.unfinished && !o.summary_only)
      throw dld::InputError("--unfinished: expected --summary too (it adds to the summary)");
    if (o.exact_coupling_for > 0 && !o.retry_failed)
      throw dld::InputError(
          "--exact-coupling-for: expected --retry-failed too (it applies to failed runs only)");
    if (o.layout.membrane_nodes > 0 && o.slurm.empty())
      throw dld::InputError("--membrane-nodes: expected --slurm too (it sizes the job's tasks)");
    if (!o.hosts.empty() && !o.slurm.empty())
      throw dld::InputError("--hosts: a SLURM task finds its hosts itself (--membrane-nodes)");
    if (!o.slurm.empty()) {
      const std::string self = fs::read_symlink("/proc/self/exe").string();
      fs::create_directories(fs::absolute(study.output) / "slurm");
      std::ofstream(o.slurm) << dld::coupler::slurm_script(
          study, resolution, runs.size(), o.jobs > 0 ? o.jobs : static_cast<int>(runs.size()), self,
          o.layout);
      fs::permissions(o.slurm, fs::perms::owner_exec, fs::perm_options::add);
      fmt::print("wrote {} ({} runs): submit with  sbatch {}\n", o.slurm, runs.size(), o.slurm);
      return 0;
    }
    if (o.list) {
      for (const auto& r : runs) {
        const std::string progress = dld::coupler::run_progress(r);
        fmt::print("{:3d}  {:24s} {}{}\n", r.index, r.name,
                   dld::coupler::state_name(dld::coupler::run_state(r)),
                   progress.empty() ? "" : ": " + progress);
      }
    }
    if (o.summary_only) write_study_summary(study, runs, resolution, o.unfinished);
    if (o.list || o.summary_only) return 0;

    int done_before = 0, failed_before = 0;
    const std::vector<const StudyRun*> to_do =
        dld::coupler::runs_to_do(chosen, done_before, failed_before, o.retry_failed);
    std::deque<const StudyRun*> queue(to_do.begin(), to_do.end());
    const int jobs = o.jobs == 0 ? default_jobs(queue, o.layout.threads) : o.jobs;
    fmt::print("dld-sweep: study {} ({}), {} runs selected: {} done, {} to run, {} at a time{}\n",
               study.name, resolution.empty() ? "default resolution" : resolution, chosen.size(),
               done_before, queue.size(), jobs,
               failed_before > 0
                   ? fmt::format("; {} failed before, left out (--retry-failed)", failed_before)
                   : "");
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);  // SLURM's time limit: checkpoint like Ctrl-C
    const std::vector<std::string> failed = Sweep(study, std::move(queue), jobs, o.dry, done_before,
                                                  placement_args(o), o.exact_coupling_for)
                                                .run();
    if (o.dry) return 0;
    if (g_interrupted) {
      fmt::print(stderr,
                 "dld-sweep: interrupted; the stopped runs resume from their checkpoints when "
                 "the sweep is started again\n");
      return 130;
    }
    if (o.index < 0) write_study_summary(study, runs, resolution);
    if (!failed.empty()) {
      fmt::print(stderr, "dld-sweep: {} runs failed: {}\n", failed.size(), fmt::join(failed, " "));
      return 1;
    }
    return 0;
  } catch (const dld::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-sweep", run_main, argc, argv);
}
