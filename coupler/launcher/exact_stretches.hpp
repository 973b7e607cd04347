// SPDX-License-Identifier: MIT
// The steps a held run ran at exact coupling instead (dld-run --exact-coupling-for), kept beside
// its checkpoints in <stem>-exact-coupling.csv: one row per stretch, first_step,last_step and the
// step it was planned to end at. A stretch that ended before its plan (interrupted, or stopped by
// the guard after a checkpoint) is finished by the next resume.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace dld::coupler {

struct ExactStretch {
  std::int64_t first = 0, last = 0;  ///< the steps run at exact coupling: [first, last)
  std::int64_t planned = 0;          ///< where it was to end (= last when it got there)
};

/// The record of a run whose files have the stem `stem` (e.g. <dir>/run):
/// <stem>-exact-coupling.csv, written by dld-run, read by dld-sweep.
inline std::string exact_stretches_file(const std::string& stem) {
  return stem + "-exact-coupling.csv";
}
/// The file's stretches, in order; none when it does not exist. Rows of two columns (files
/// written before the plan was kept) count as finished. Throws InputError naming the file and
/// line for a row that is not numbers.
std::vector<ExactStretch> read_exact_stretches(const std::string& path);
/// Appends one stretch (the header first when the file is new).
void append_exact_stretch(const std::string& path, const ExactStretch& s);
/// Where an unfinished stretch that ended at `from` was to end; 0 when there is none.
std::int64_t pending_exact_end(const std::vector<ExactStretch>& stretches, std::int64_t from);

}  // namespace dld::coupler
