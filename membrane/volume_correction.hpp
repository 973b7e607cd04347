// SPDX-License-Identifier: MIT
// A cell's enclosed volume restored to its rest value by the smallest node displacement that does
// it: x_i += lambda g_i, with g_i = dV/dx_i (V from the divergence theorem) and lambda such that
// V(x + lambda g) = V0 (a projection onto the constraint V = V0 along its gradient, as SHAKE
// projects bond constraints: Ryckaert, Ciccotti & Berendsen, J. Comput. Phys. 23 (1977) 327).
// Numerics, not physics: the immersed boundary's interpolated velocity is not exactly
// divergence-free across a membrane, so a cell held under load loses volume that a real membrane
// keeps (docs/results-history.md, "Volume loss"); [coupling] volume_correction_every sets how often
// this gives it back (0: never, the default).
#pragma once
#include <vector>

#include "membrane/mesh.hpp"

namespace dld::membrane {

/// Moves the nodes x (one cell, lattice lengths) so that the volume they enclose is v0 to
/// round-off (1e-13 relative); returns the volume change made, relative to v0 (0 and x untouched
/// if it is v0 already). The centroid stays: the gradient sums to zero over a closed surface.
double restore_volume(Eigen::Ref<Points> x, const std::vector<Face>& faces, double v0);

}  // namespace dld::membrane
