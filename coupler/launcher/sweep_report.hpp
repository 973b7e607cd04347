// SPDX-License-Identifier: MIT
// What dld-sweep leaves besides the runs: the state of each run on disk, the study's summary table
// (one row per finished run: its axis values, wall time and the analysis figures) and a SLURM
// job-array script that runs the same study on a cluster.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "coupler/launcher/study.hpp"

namespace dld::coupler {

enum class RunState { kWaiting, kPartial, kFailed, kDone };

/// done: <dir>/done.toml exists; failed: its last attempt (attempts.csv) ended with an error, not
/// an interruption (exit code 130) or a killed sweep (-1), and none has started since
/// (attempt-running.csv); partial: a checkpoint exists; else waiting.
RunState run_state(const StudyRun& run);
/// Whether the run has a checkpoint to resume from.
bool has_checkpoint(const StudyRun& run);
const char* state_name(RunState s);
/// The runs of `chosen` still to run, partial ones first, each group in the given order: a sweep
/// started again finishes what it began before it begins anything new (so a run under way never
/// waits for a slot behind a new one). A failed run is left out (its resume would fail again the
/// same way) unless `retry_failed`, which queues it with the partial ones. `done` and `failed` get
/// the numbers done and left out.
std::vector<const StudyRun*> runs_to_do(const std::vector<const StudyRun*>& chosen, int& done,
                                        int& failed, bool retry_failed = false);
/// Wall time of all attempts of a run so far (seconds), from <dir>/attempts.csv and the running
/// attempt's <dir>/attempt-running.csv.
double run_wall_s(const StudyRun& run);
/// The steps a run ran at exact coupling instead of its setting's held one (dld-run
/// --exact-coupling-for, <dir>/run-exact-coupling.csv), as "first-last;first-last"; "" if none.
/// With before_step >= 0 only the stretches that began before it.
std::string exact_coupling_stretches(const StudyRun& run, std::int64_t before_step = -1);
/// How far a run got, for --list: the newest progress line of its membrane logs (step and the
/// slowest process's pillars and its ETA, e.g. "step 4145000, 17.00/20 pillars, ETA 2.1 h") and
/// its wall time so far (run_wall_s), and its exact-coupling stretches; "" when there is none.
std::string run_progress(const StudyRun& run);
/// Appends one attempt (exit code, wall time) to <dir>/attempts.csv.
void record_attempt(const StudyRun& run, int exit_code, double wall_s);
/// The running attempt's wall time so far, in <dir>/attempt-running.csv (rewritten through a
/// rename): a sweep that is killed (SIGKILL, the end of a session or a node) records nothing
/// else. record_attempt removes it; fold_lost_attempt, called before a run starts, moves one left
/// by a killed sweep into attempts.csv with exit code -1, so no wall time is lost.
void note_running_attempt(const StudyRun& run, double wall_s);
void fold_lost_attempt(const StudyRun& run);
/// Marks a run finished (written last, through a temporary file and a rename).
void mark_done(const StudyRun& run, double wall_s);

/// Writes <output>/<resolution>/summary.csv from the finished runs' <dir>/run-summary.csv (written
/// by dld-analyze) and prints it as a table; returns the CSV path.
std::string write_summary(const Study& study, const std::vector<StudyRun>& runs,
                          const std::string& resolution);
/// Where dld-sweep --summary --unfinished analyses a partial or failed run as it stands.
std::filesystem::path so_far_dir(const StudyRun& run);
/// Writes <output>/<resolution>/summary-unfinished.csv: one row per partial or failed run with an
/// analysis in so_far_dir (each cell over the pillars it passed, at most the study's), with its
/// state; prints it; returns the CSV path, or "" (and no file) when there is no such run.
std::string write_unfinished_summary(const Study& study, const std::vector<StudyRun>& runs,
                                     const std::string& resolution);

/// How each task of a SLURM array spreads its run: membrane_nodes 0 keeps the whole run on one
/// node (one task of 2 cores); M > 0 gives it 1 + M nodes, the fluid on the first and
/// `membrane_processes` membrane processes (default M) on the other M (dld-run --hosts, which
/// starts them through srun).
struct SlurmLayout {
  int membrane_nodes = 0, membrane_processes = 0;
  int threads = 0;  ///< each program's threads (dld-run --threads) and a task's cpus; 0: 2 cpus
};

/// A SLURM job-array script: task i runs `dld-sweep STUDY --resolution R --index i`, at most
/// `jobs` at once; the summary is made afterwards with `dld-sweep STUDY --summary`.
std::string slurm_script(const Study& study, const std::string& resolution, std::size_t runs,
                         int jobs, const std::string& sweep_exe, const SlurmLayout& layout = {});

}  // namespace dld::coupler
