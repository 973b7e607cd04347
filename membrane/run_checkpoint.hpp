// SPDX-License-Identifier: MIT
// Membrane checkpoints of a coupled run: the node positions of this process's cells, the
// trajectory samples so far and the step, in an HDF5 file written through a temporary file and a
// rename (the one before is kept as `path`.prev, as the fluid does in fluid/checkpoint.hpp, so the
// two sides always share a step to resume from).
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
  std::vector<double> rows;  ///< trajectory samples (see coupled_main.cpp)
};

void write_run_checkpoint(const std::string& path, const RunCheckpoint& c);
/// Throws InputError naming the file and field when it is missing or does not fit `expected`
/// (scene hash, first cell, cell and node counts).
RunCheckpoint read_run_checkpoint(const std::string& path, const RunCheckpoint& expected);

}  // namespace dld::membrane
