// SPDX-License-Identifier: MIT
// Smallest node gaps of a set of cells in the DLD box: between nodes of different cells (across
// periodic y and the shifted periodic x), to the z walls and to the pillar. What a packed initial
// state must keep above the contact range.
#pragma once
#include <vector>

#include "membrane/mesh.hpp"
#include "shared/dld_geometry.hpp"

namespace dld::membrane {

/// Smallest distances [lattice lengths] (any unit the positions and box share).
struct Clearances {
  double cells = 0.0;   ///< node to node of another cell (or its image); capped, see below
  double walls = 0.0;   ///< node to z = 0 or z = depth
  double pillar = 0.0;  ///< node to the pillar surface (negative: inside)
  double min() const { return std::min(cells, std::min(walls, pillar)); }
};

/// x holds the cells one after another, `nodes_per_cell` nodes each, unwrapped (a cell in one
/// piece). Cell gaps larger than `cap` are reported as `cap` (the search stops there).
Clearances clearances(const Points& x, int nodes_per_cell, const DldCell& box, double cap);

/// Nodes of any cell lying inside another cell or its periodic image (surfaces that cross between
/// nodes, which node gaps alone would miss): winding number over the other cell's faces, `faces`
/// those of every cell.
int nodes_inside_other_cells(const Points& x, const std::vector<Face>& faces, int nodes_per_cell,
                             const DldCell& box);

/// Moves each cell as a whole so that its centroid lies in the box [0, lambda)^2, honouring the
/// shifted x boundary (z untouched).
void fold_cells_into_box(Points& x, int nodes_per_cell, const DldCell& box);

}  // namespace dld::membrane
