// SPDX-License-Identifier: MIT
// The fused stream + collide kernel over the fluid runs of a Lattice. Structure of arrays, stride
// padded_size: read each node's incoming populations (the pull slots, through one view), collide
// with the Collision policy's relax() (fluid/collision/, inlined: no per-node dispatch), write the
// post-collision values (through another view). The views are two arrays (the pull update) or
// one array in the in-place update's two layouts (fluid/population_view.hpp), which moves a third
// less memory and is bound by that traffic on the DLD lattice (docs/performance.md). Compile-time
// switches keep the optional per-node force and relaxation-time fields out of the loop when a
// scene has none (no cost unless used).
//
// Vectorisation: runs are cut into blocks of kLanes consecutive nodes; within a block the 19
// directions are unrolled at compile time (the velocity components become constants), and the
// loop over lanes is a plain SIMD loop; a run's last block is masked.
// The population arrays must extend kPopulationPadding values past the last node (see below).
#pragma once
#include <cstddef>
#include <type_traits>
#include <utility>

#include "fluid/collision.hpp"
#include "fluid/d3q19.hpp"
#include "fluid/lattice.hpp"
#include "fluid/population_view.hpp"

namespace dld::fluid {

/// Totals over the fluid nodes of one update, from the same moments the collision used.
struct FlowSums {
  double mass = 0, momentum_x = 0, momentum_y = 0, momentum_z = 0;
};

struct KernelParams {
  double tau = 1.0;             ///< relaxation time where no tau field is given
  double magic = 3.0 / 16.0;    ///< TRT Lambda
  double force[3] = {0, 0, 0};  ///< uniform body force density (lattice units)
  const double* force_field[3] = {nullptr, nullptr, nullptr};  ///< per node, added to `force`
  /// Per-node relaxation rates omega+ and omega- (fluid/relaxation_field.hpp), or none.
  const double* rate_plus = nullptr;
  const double* rate_minus = nullptr;
  /// With a force field (coupled runs), the kernel also stores each fluid node's velocity here
  /// (the u of the collision, Guo's half-force shift included): the immersed boundary interpolates
  /// it without a second pass over the populations.
  double* velocity[3] = {nullptr, nullptr, nullptr};
};

/// Values allocated past the end of a population array so masked lanes can read safely.
inline constexpr std::size_t kPopulationPadding = 64;
/// Prefetch distance in values (8 blocks of 8 nodes ahead); a prefetch past an array never faults.
inline constexpr std::ptrdiff_t kPrefetchDistance = 64;

namespace detail {

/// Updates `count` <= kW consecutive nodes starting at padded index `node`. Lanes past `count`
/// read (padded, allocated) memory and compute throw-away values that are neither stored nor
/// summed, so a run's tail costs one masked block instead of a scalar loop.
/// in_base[i] + y is the pull slot (i, y - c_i) of node y, out_base[i] + y its post(i, y)
/// (fluid/population_view.hpp); the two may be the same array (the in-place update: a node writes
/// only slots that it alone reads, and it reads all of them before it writes).
template <typename Collision, bool kForceField, bool kTauField, int kW, bool kMasked>
inline void update_block(const double* const* in_base, double* const* out_base, std::size_t node,
                         int count, const KernelParams& p, double op_uniform, double om_uniform,
                         FlowSums& acc) {
  // Per-direction base pointers make every access unit-stride in the lane index (no gathers).
  const double* in[D3Q19::q];
  double* out[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) {
    in[i] = in_base[i] + node;
    out[i] = out_base[i] + node;
  }
  // Software prefetch kPrefetchDistance values ahead on all 38 streams: the hardware prefetchers
  // do not follow that many streams, and the kernel otherwise stalls on memory it does not
  // saturate (128^3 box, 2 threads: 1.17-1.45x, bench_fluid side by side, 2026-11-30).
  if constexpr (!kMasked) {
    for (int i = 0; i < D3Q19::q; ++i) {
      __builtin_prefetch(in[i] + kPrefetchDistance, 0, 3);
      __builtin_prefetch(out[i] + kPrefetchDistance, 1, 3);
    }
  }
  const double* force_x = kForceField ? p.force_field[0] + node : nullptr;
  const double* force_y = kForceField ? p.force_field[1] + node : nullptr;
  const double* force_z = kForceField ? p.force_field[2] + node : nullptr;
  const double* rate_plus = kTauField ? p.rate_plus + node : nullptr;
  const double* rate_minus = kTauField ? p.rate_minus + node : nullptr;
  double* vel_x = kForceField ? p.velocity[0] + node : nullptr;
  double* vel_y = kForceField ? p.velocity[1] + node : nullptr;
  double* vel_z = kForceField ? p.velocity[2] + node : nullptr;
  // The field streams too (up to 8 more): unprefetched, they cost the one-thread coupled step
  // most of what the fields add to it.
  if constexpr (!kMasked && kForceField) {
    for (int a = 0; a < 3; ++a) {
      __builtin_prefetch(p.force_field[a] + node + kPrefetchDistance, 0, 3);
      __builtin_prefetch(p.velocity[a] + node + kPrefetchDistance, 1, 3);
    }
  }
  if constexpr (!kMasked && kTauField) {
    __builtin_prefetch(rate_plus + kPrefetchDistance, 0, 3);
    __builtin_prefetch(rate_minus + kPrefetchDistance, 0, 3);
  }
  double mass = 0, mx = 0, my = 0, mz = 0;
#pragma omp simd reduction(+ : mass, mx, my, mz)
  for (int l = 0; l < kW; ++l) {
    double f[D3Q19::q];
    [&]<int... I>(std::integer_sequence<int, I...>) {
      ((f[I] = in[I][l]), ...);
    }
    (std::make_integer_sequence<int, D3Q19::q>{});
    double fx = p.force[0], fy = p.force[1], fz = p.force[2];
    if constexpr (kForceField) {
      fx += force_x[l];
      fy += force_y[l];
      fz += force_z[l];
    }
    double op = op_uniform, om = om_uniform;
    if constexpr (kTauField) {
      op = rate_plus[l];
      om = rate_minus[l];
    }
    double rho = 0, jx = 0, jy = 0, jz = 0;
    [&]<int... I>(std::integer_sequence<int, I...>) {
      ((rho += f[I]), ...);
      ((jx += kC<I, 0> * f[I]), ...);
      ((jy += kC<I, 1> * f[I]), ...);
      ((jz += kC<I, 2> * f[I]), ...);
    }
    (std::make_integer_sequence<int, D3Q19::q>{});
    const double inv = 1.0 / rho;
    const double ux = (jx + 0.5 * fx) * inv, uy = (jy + 0.5 * fy) * inv, uz = (jz + 0.5 * fz) * inv;
    // The operator's post-collision populations (fluid/collision/), stored unless masked. f stays
    // read-only and each value goes straight to `out`, and the operators are always inlined:
    // an operator writing f in place, or a call left in the SIMD loop, keeps the lanes' arrays in
    // memory and made the step 4.5x slower (bench_fluid BM_DldCell, 2026-12-02).
    const bool live = !kMasked || l < count;
    if constexpr (kForceField) {
      if (live) {
        vel_x[l] = ux;
        vel_y[l] = uy;
        vel_z[l] = uz;
      }
    }
    Collision::relax(f, NodeState{rho, ux, uy, uz, fx, fy, fz, op, om},
                     [&]<int I>(std::integral_constant<int, I>, double value) {
                       if (live) out[I][l] = value;
                     });
    mass += live ? rho : 0.0;
    mx += live ? jx + 0.5 * fx : 0.0;
    my += live ? jy + 0.5 * fy : 0.0;
    mz += live ? jz + 0.5 * fz : 0.0;
  }
  acc.mass += mass;
  acc.momentum_x += mx;
  acc.momentum_y += my;
  acc.momentum_z += mz;
}

}  // namespace detail

/// One update: reads pull slots through `in`, writes post-collision populations through `out`
/// (views of two arrays, or of one array in the in-place update's two states).
template <typename Collision, bool kForceField, bool kTauField>
FlowSums stream_collide(const Lattice& L, const PopulationView& in, const PopulationView& out,
                        const KernelParams& p) {
  constexpr int kLanes = 8;
  const auto& segs = L.segments();
  const auto rates = Collision::rates(p.tau, p.magic);
  const double* in_base[D3Q19::q];
  double* out_base[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) {
    in_base[i] = in.base[i] - L.offset(i);
    out_base[i] = out.base[i];
  }
  double mass = 0, mx = 0, my = 0, mz = 0;
#pragma omp parallel for schedule(static) reduction(+ : mass, mx, my, mz)
  for (std::size_t k = 0; k < segs.size(); ++k) {
    FlowSums acc;
    std::size_t node = segs[k].begin;
    int len = segs[k].length;
    for (; len >= kLanes; len -= kLanes, node += kLanes)
      detail::update_block<Collision, kForceField, kTauField, kLanes, false>(
          in_base, out_base, node, kLanes, p, rates.plus, rates.minus, acc);
    if (len > 0)
      detail::update_block<Collision, kForceField, kTauField, kLanes, true>(
          in_base, out_base, node, len, p, rates.plus, rates.minus, acc);
    mass += acc.mass;
    mx += acc.momentum_x;
    my += acc.momentum_y;
    mz += acc.momentum_z;
  }
  return {mass, mx, my, mz};
}

/// The pull update from `src` to `dst` (two arrays in the pull layout).
template <typename Collision, bool kForceField, bool kTauField>
FlowSums stream_collide(const Lattice& L, const double* src, double* dst, const KernelParams& p) {
  return stream_collide<Collision, kForceField, kTauField>(
      L, PopulationView(L, const_cast<double*>(src), PopulationLayout::kPull),
      PopulationView(L, dst, PopulationLayout::kPull), p);
}

}  // namespace dld::fluid
