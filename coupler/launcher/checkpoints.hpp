// SPDX-License-Identifier: MIT
// Which checkpoints a resumed run starts from: every program keeps its newest checkpoint and the
// one before (.prev); the run resumes at the newest step the fluid and a set of membrane
// checkpoints holding every cell once have. The membrane set may come from another split of the
// cells (another number of membrane processes): each process of the resumed run takes its share
// from all of them (membrane/run_checkpoint.hpp).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dld::coupler {

/// Step of a checkpoint file (attribute `step` of `group`), or -1 if missing or unreadable.
std::int64_t checkpoint_step(const std::string& path, const std::string& group);

struct ResumePoint {
  std::int64_t step = 0;
  std::string fluid;               ///< the fluid's checkpoint (group /fluid)
  std::vector<std::string> cells;  ///< membrane checkpoints of that step holding cells 0..N-1 once
};

/// The newest step at which `fluid` (or its .prev) and some of `membrane_files` (each with its
/// .prev; group /membrane, attributes first_cell and cells) hold the whole run: every one of
/// `total_cells` cells in exactly one file. Throws dld::InputError naming each file found with its
/// step and cells, and each of the first `expected_files` that is missing, when there is none.
ResumePoint coupled_resume_point(const std::string& fluid,
                                 const std::vector<std::string>& membrane_files, int total_cells,
                                 std::size_t expected_files);

}  // namespace dld::coupler
