// SPDX-License-Identifier: MIT
// The axis weights of the default kernel (Peskin 4) for many markers at once, SIMD across markers
// (fluid/ib_footprint.hpp computes them one marker at a time): the folding of x through the
// shifted face, the floor and the one square root per axis are most of a footprint's cost.
// Same operations in the same order as axis_weights<4>, so the same bits.
#pragma once
#include <cstdint>

namespace dld::fluid {

inline constexpr int kIbBatch = 16;

struct Peskin4AxisBatch {
  double w[3][4][kIbBatch];  ///< axis (x, y, z), node, marker: unnormalised weights
  /// each axis's first support node: x folded into the box, y wrapped into [0, ny)
  double first[3][kIbBatch];
};

/// Markers index[0..n), n <= kIbBatch, of `positions` (3 per marker, lattice units): x folded
/// into [0, nx) (y lowered by `shift` per box), then the Peskin-4 weights on each axis. A
/// non-finite position gives non-finite entries (the caller checks the position).
void peskin4_axis_batch(const double* positions, const std::uint32_t* index, int n, double nx,
                        double ny, double shift, Peskin4AxisBatch& out);

}  // namespace dld::fluid
