// SPDX-License-Identifier: MIT
// The fused pull-stream + collide kernel over the fluid runs of a Lattice. Two population arrays
// (structure of arrays, stride padded_size): read the post-collision values of the neighbours in
// `src`, collide, write to `dst`. Compile-time switches keep the optional per-node force and
// relaxation-time fields out of the loop when a scene has none (no cost unless used).
#pragma once
#include <cstddef>

#include "fluid/collision.hpp"
#include "fluid/lattice.hpp"

namespace dld::fluid {

/// Totals over the fluid nodes of one update, from the same moments the collision used.
struct FlowSums {
  double mass = 0, momentum_x = 0, momentum_y = 0, momentum_z = 0;
};

struct KernelParams {
  double tau = 1.0;          ///< relaxation time where no tau field is given
  double magic = 3.0 / 16.0; ///< TRT Lambda
  double force[3] = {0, 0, 0};       ///< uniform body force density (lattice units)
  const double* force_field[3] = {nullptr, nullptr, nullptr};  ///< per node, added to `force`
  const double* tau_field = nullptr;                         ///< per node relaxation time
};

template <typename Collision, bool kForceField, bool kTauField>
FlowSums stream_collide(const Lattice& L, const double* __restrict src, double* __restrict dst,
                        const KernelParams& p) {
  const std::size_t n = L.padded_size();
  const auto& segs = L.segments();
  const auto rates = Collision::rates(p.tau, p.magic);
  std::ptrdiff_t off[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) off[i] = L.offset(i);
  double mass = 0, mx = 0, my = 0, mz = 0;
#pragma omp parallel for schedule(static) reduction(+ : mass, mx, my, mz)
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const std::size_t b = segs[s].begin;
    const int len = segs[s].length;
#pragma omp simd reduction(+ : mass, mx, my, mz)
    for (int x = 0; x < len; ++x) {
      const std::size_t node = b + static_cast<std::size_t>(x);
      double f[D3Q19::q];
#pragma GCC unroll 19
      for (int i = 0; i < D3Q19::q; ++i) f[i] = src[i * n + node - off[i]];
      double fx = p.force[0], fy = p.force[1], fz = p.force[2];
      if constexpr (kForceField) {
        fx += p.force_field[0][node];
        fy += p.force_field[1][node];
        fz += p.force_field[2][node];
      }
      double op = rates.plus, om = rates.minus;
      if constexpr (kTauField) {
        const auto r = Collision::rates(p.tau_field[node], p.magic);
        op = r.plus;
        om = r.minus;
      }
      const Moments m = collide(f, op, om, fx, fy, fz);
#pragma GCC unroll 19
      for (int i = 0; i < D3Q19::q; ++i) dst[i * n + node] = f[i];
      mass += m.rho;
      mx += m.rho * m.ux;
      my += m.rho * m.uy;
      mz += m.rho * m.uz;
    }
  }
  return {mass, mx, my, mz};
}

}  // namespace dld::fluid
