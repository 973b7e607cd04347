// SPDX-License-Identifier: MIT
// Dense initial states (SPEC section 6): N cells placed at random, flat (symmetry axis along z),
// without overlapping each other, the pillar or the z walls, across periodic y and shifted
// periodic x. Random sequential addition stalls far below the study's 45.6 %, so the cells grow:
// they start shrunk at random positions and angles, then their rest size rises step by step to
// full size while an energy minimisation (L-BFGS over all nodes) resolves the overlaps with the
// membrane mechanics and a contact repulsion, so cells move, turn and deform to make room.
// All lengths in lattice units.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "membrane/clearance.hpp"
#include "membrane/mesh.hpp"
#include "shared/dld_geometry.hpp"

namespace dld::membrane {

struct PackOptions {
  int count = 1;           ///< cells
  std::uint64_t seed = 1;  ///< random positions and angles
  /// Every node gap (cell-cell, walls, pillar) must end above this [lattice lengths]: the
  /// contact range of the scene.
  double clearance = 1.0;
  double start_scale = 0.5;  ///< size of the cells when placed, relative to the rest shape
  double scale_step = 0.02;  ///< growth per stage (relative size)
  /// L-BFGS iterations over all stages before giving up (the study's states need about 1200).
  int max_iterations = 20000;
};

struct PackReport {
  int stages = 0;
  int iterations = 0;        ///< L-BFGS iterations over all stages
  double seconds = 0.0;      ///< wall time
  double cpu_seconds = 0.0;  ///< processor time of this process (the machine may be shared)
  Clearances gaps;           ///< of the final state [lattice lengths]
};

struct PackedCells {
  Points positions;  ///< cells one after another, each in one piece, centroid in the box
  int nodes_per_cell = 0;
  PackReport report;
};

/// Largest angle [degrees] between a cell's short axis (smallest eigenvalue of its node gyration
/// tensor) and z: how flat the cells of a state are (0 for cells lying flat).
double largest_tilt_deg(const Points& x, int nodes_per_cell);

/// Progress lines (stage, scale, gaps); may be empty.
using PackLog = std::function<void(const std::string&)>;

/// Packs `o.count` copies of `reference` (rest shape, symmetry axis along z, any position) into
/// `box`. Deterministic for a given (reference, box, options). Throws InputError when the cells
/// cannot be placed or the final state is not clear of the contact range.
PackedCells pack_cells(const TriMesh& reference, const DldCell& box, const PackOptions& o,
                       const PackLog& log = {});

}  // namespace dld::membrane
