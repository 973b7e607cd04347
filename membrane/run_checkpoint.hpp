// SPDX-License-Identifier: MIT
// Membrane checkpoints of a coupled run: the node positions of this process's cells, the
// trajectory samples so far and the step, in an HDF5 file written through a temporary file and a
// rename (the one before is kept as `path`.prev, as the fluid does in fluid/checkpoint.hpp, so the
// two sides always share a step to resume from).
// A checkpoint holds cells [first_cell, first_cell + cells) of the scene; a resumed process takes
// its share from the checkpoints of any split (issue 14: the cells' state must not depend on how
// many membrane processes wrote it), so a run can continue with a different number of them.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "membrane/mesh.hpp"

namespace dld::membrane {

struct RunCheckpoint {
  std::int64_t step = 0;
  std::string scene_hash;
  int first_cell = 0, cells = 0, nodes_per_cell = 0;
  Points positions;          ///< lattice units, unwrapped (device frame)
  std::vector<double> rows;  ///< trajectory samples: step, then 4 values per cell (coupled_main)
};

void write_run_checkpoint(const std::string& path, const RunCheckpoint& c);

/// Cells [expected.first_cell, + expected.cells) from `paths`, the checkpoints of one step
/// written by any split of the cells (this process's own file, or every process's). Throws
/// InputError naming the file and field when one is missing or unreadable, belongs to another
/// scene or mesh, is at another step or sample steps than the others, claims a cell another file
/// claims too, or when no file holds one of the wanted cells.
RunCheckpoint read_run_checkpoints(const std::vector<std::string>& paths,
                                   const RunCheckpoint& expected);

}  // namespace dld::membrane
