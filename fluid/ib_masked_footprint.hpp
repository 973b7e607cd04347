// SPDX-License-Identifier: MIT
// The footprint of an immersed-boundary marker whose support reaches the pillar (ImmersedBoundary::
// masked_footprint): the pillar is solid at every height, so dropping its nodes and renormalising
// (what stencil() does node by node) keeps the weights a product of a per-row x factor and the y
// and z weights. Rows of W consecutive x nodes are then read and written as short vectors, as for
// a separable footprint (fluid/ib_footprint.hpp), instead of a list of up to W^3 nodes.
// Lattice units; node (i, j, k) at (i + 1/2, j + 1/2, k + 1/2).
#pragma once
#include <cstddef>

#include "fluid/ib_footprint.hpp"

namespace dld::fluid {

template <int W>
struct IbMaskedFootprint {
  double wx[W][W];       ///< per y row: x weights, zero at solid columns; carry the normalisation
  double wy[W], wz[W];   ///< y and z weights (z layers beyond a wall zero, as IbFootprint)
  std::size_t row[W];    ///< padded offset of each y row within a layer, (j + 1) px
  std::size_t layer[W];  ///< padded offset of each z layer, (k + 1) px py
  std::size_t x0;        ///< padded x offset of the first column, i0 + 1
};

/// Adds force f (3 components) times each node's weight to the field (three padded arrays); solid
/// nodes get + 0 (their force stays zero).
template <int W>
inline void spread_footprint(const IbMaskedFootprint<W>& p, const double* f,
                             double* const field[3]) {
  if constexpr (W == 4) {
    using detail::V4;
    V4 g0[4], g1[4], g2[4];
    for (int b = 0; b < 4; ++b) {
      const V4 wx = detail::load4(p.wx[b]);
      g0[b] = wx * f[0], g1[b] = wx * f[1], g2[b] = wx * f[2];
    }
    detail::spread_rows4<4>(p.wz, p.wy, p.layer, p.row, p.x0, g0, g1, g2, field);
    return;
  }
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b) {
      const double w = p.wz[c] * p.wy[b];
      const std::size_t n = p.layer[c] + p.row[b] + p.x0;
      for (int a = 0; a < W; ++a)
        for (int d = 0; d < 3; ++d) field[d][n + a] += p.wx[b][a] * w * f[d];
    }
}

/// The weighted mean of the velocity arrays over the footprint, into u (3 components).
template <int W>
inline void interpolate_footprint(const IbMaskedFootprint<W>& p, const double* const v[3],
                                  double* u) {
  if constexpr (W == 4) {
    using detail::V4;
    V4 a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0;
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 4; ++b) {
        const V4 w = (p.wz[c] * p.wy[b]) * detail::load4(p.wx[b]);
        const std::size_t n = p.layer[c] + p.row[b] + p.x0;
        a0 += w * detail::load4(v[0] + n);
        a1 += w * detail::load4(v[1] + n);
        a2 += w * detail::load4(v[2] + n);
      }
    u[0] = (a0[0] + a0[1]) + (a0[2] + a0[3]);
    u[1] = (a1[0] + a1[1]) + (a1[2] + a1[3]);
    u[2] = (a2[0] + a2[1]) + (a2[2] + a2[3]);
    return;
  }
  u[0] = u[1] = u[2] = 0.0;
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b) {
      const double w = p.wz[c] * p.wy[b];
      const std::size_t n = p.layer[c] + p.row[b] + p.x0;
      for (int a = 0; a < W; ++a)
        for (int d = 0; d < 3; ++d) u[d] += p.wx[b][a] * w * v[d][n + a];
    }
}

}  // namespace dld::fluid
