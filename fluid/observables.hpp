// SPDX-License-Identifier: MIT
// Measurements on a fluid-only DLD cell: the flux profile through the gap above the pillar and
// the streamline separation distance (the width of the band next to the pillar that carries the
// fraction eps = d/lambda of the gap flux). Lattice units unless a name says otherwise.
#pragma once
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "shared/dld_geometry.hpp"

namespace dld::fluid {

/// Depth-integrated u_x across the gap between the pillar and its neighbour above (+y), on the
/// plane x = pillar centre (the narrowest cross-section).
struct GapProfile {
  double width = 0;       ///< gap width G
  std::vector<double> y;  ///< node positions measured from the lower pillar surface, in (0, G)
  std::vector<double> q;  ///< integral of u_x over z at those positions
  double flux = 0;        ///< integral of q over the gap (q taken linear, zero on both surfaces)
};

GapProfile gap_profile(const FluidSolver& solver, const DldCell& cell_lu);

/// Width s of the band [0, s] next to the lower pillar that carries `fraction` of the gap flux.
double band_width(const GapProfile& profile, double fraction);

}  // namespace dld::fluid
