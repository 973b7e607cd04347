// SPDX-License-Identifier: MIT
// The separable footprint of an immersed-boundary marker (Peskin 2002: the kernel is a product of
// one-dimensional weights): W x-weights, W y-rows and W z-layers, no list of W^3 nodes. A marker
// whose support lies in one box, away from every solid node and z wall, has weights that need
// no renormalisation beyond their product's sum, and its W^2 rows of W consecutive x nodes are
// read and written as short vectors. Markers across the shifted x face take the split footprint
// (below), those by the pillar a masked one (fluid/ib_masked_footprint.hpp), any other near a
// solid ImmersedBoundary::stencil(). Lattice units; node (i, j, k) at (i + 1/2, j + 1/2, k + 1/2).
#pragma once
#include <cmath>
#include <cstddef>
#if defined(__AVX512VL__)
#include <immintrin.h>
#endif

#include "fluid/ib_kernel.hpp"

namespace dld::fluid {

template <int W>
struct IbFootprint {
  double wx[W], wy[W], wz[W];  ///< wx carries the normalisation: sum of wx wy wz products = 1
  std::size_t row[W];          ///< padded offset of each y row within a layer, (j + 1) px
  std::size_t layer[W];        ///< padded offset of each z layer, (k + 1) px py
  std::size_t x0;              ///< padded x offset of the first column, i0 + 1
};

namespace detail {
using V4 = double __attribute__((vector_size(32)));  // 4 consecutive x nodes
inline V4 load4(const double* p) {
  V4 v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
inline void store4(double* p, V4 v) {
  __builtin_memcpy(p, &v, sizeof v);
}

/// The rows of a 4-point spread: field[d][node(c, b) + a] += wz[c] wy[b] g_d[b][a], where g_d
/// is the x weights times force component d, one for every row (kRowsOfG = 1, a separable
/// footprint) or one per y row (4, a masked footprint). Everything the rows need is in locals
/// first: the field's stores could otherwise alias the weights and the field pointers (behind
/// OpenMP's shared-variable struct), which the compiler would then reload after every store.
template <int kRowsOfG>
inline void spread_rows4(const double* wz, const double* wy, const std::size_t* layer,
                         const std::size_t* row, std::size_t x0, const V4* g0, const V4* g1,
                         const V4* g2, double* const field[3]) {
  double* const f0 = field[0];
  double* const f1 = field[1];
  double* const f2 = field[2];
  double wzy[16];
  std::size_t node[16];
  for (int c = 0; c < 4; ++c)
    for (int b = 0; b < 4; ++b) {
      wzy[4 * c + b] = wz[c] * wy[b];
      node[4 * c + b] = layer[c] + row[b] + x0;
    }
  for (int r = 0; r < 16; ++r) {
    const double w = wzy[r];
    const std::size_t n = node[r];
    const int b = kRowsOfG == 1 ? 0 : r % 4;
    store4(f0 + n, load4(f0 + n) + w * g0[b]);
    store4(f1 + n, load4(f1 + n) + w * g1[b]);
    store4(f2 + n, load4(f2 + n) + w * g2[b]);
  }
}
}  // namespace detail

/// Weights of the W nodes a..a+W-1 around coordinate `c` on one axis (the first node is
/// floor(c - 1/2 - h) + 1), into w; returns that first node.
template <int W>
inline int axis_weights(IbKernel kernel, double c, double* w) {
  const int first = static_cast<int>(std::floor(c - 0.5 - 0.5 * W)) + 1;
  if constexpr (W == 4) {
    if (kernel == IbKernel::kPeskin4) {
      // All four weights share one square root: with s = c - 1/2 - (first + 1) in [0, 1), the
      // distances are 1 + s, s, 1 - s, 2 - s and 1 + 4 s - 4 s^2 is the radicand of each.
      const double s = c - 0.5 - (first + 1);
      const double q = std::sqrt(1.0 + 4.0 * s - 4.0 * s * s);
      w[0] = (3.0 - 2.0 * s - q) * 0.125;
      w[1] = (3.0 - 2.0 * s + q) * 0.125;
      w[2] = (1.0 + 2.0 * s + q) * 0.125;
      w[3] = (1.0 + 2.0 * s - q) * 0.125;
      return first;
    }
  }
  for (int a = 0; a < W; ++a) w[a] = phi(kernel, first + a + 0.5 - c);
  return first;
}

/// Adds force f (3 components) times each node's weight to the field (three padded arrays).
template <int W>
inline void spread_footprint(const IbFootprint<W>& p, const double* f, double* const field[3]) {
  if constexpr (W == 4) {
    using detail::V4;
    const V4 wx = detail::load4(p.wx);
    const V4 g0 = wx * f[0], g1 = wx * f[1], g2 = wx * f[2];
    detail::spread_rows4<1>(p.wz, p.wy, p.layer, p.row, p.x0, &g0, &g1, &g2, field);
    return;
  }
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b) {
      const double w = p.wz[c] * p.wy[b];
      const std::size_t n = p.layer[c] + p.row[b] + p.x0;
      const double g0 = w * f[0], g1 = w * f[1], g2 = w * f[2];
      double* __restrict f0 = field[0] + n;
      double* __restrict f1 = field[1] + n;
      double* __restrict f2 = field[2] + n;
      for (int a = 0; a < W; ++a) {
        f0[a] += p.wx[a] * g0;
        f1[a] += p.wx[a] * g1;
        f2[a] += p.wx[a] * g2;
      }
    }
}

/// The weighted mean of the velocity arrays over the footprint, into u (3 components).
template <int W>
inline void interpolate_footprint(const IbFootprint<W>& p, const double* const v[3], double* u) {
  if constexpr (W == 4) {
    // Each of the 16 rows is one 4-wide load per component; the x weights come last.
    using detail::V4;
    V4 a0 = {0, 0, 0, 0}, a1 = a0, a2 = a0;
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 4; ++b) {
        const double w = p.wz[c] * p.wy[b];
        const std::size_t n = p.layer[c] + p.row[b] + p.x0;
        a0 += w * detail::load4(v[0] + n);
        a1 += w * detail::load4(v[1] + n);
        a2 += w * detail::load4(v[2] + n);
      }
    const V4 wx = detail::load4(p.wx);
    a0 *= wx, a1 *= wx, a2 *= wx;
    u[0] = (a0[0] + a0[1]) + (a0[2] + a0[3]);
    u[1] = (a1[0] + a1[1]) + (a1[2] + a1[3]);
    u[2] = (a2[0] + a2[1]) + (a2[2] + a2[3]);
    return;
  }
  double acc[3][W] = {};
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b) {
      const double w = p.wz[c] * p.wy[b];
      const std::size_t n = p.layer[c] + p.row[b] + p.x0;
      for (int a = 0; a < W; ++a) {
        acc[0][a] += w * v[0][n + a];
        acc[1][a] += w * v[1][n + a];
        acc[2][a] += w * v[2][n + a];
      }
    }
  for (int d = 0; d < 3; ++d) {
    double s = 0.0;
    for (int a = 0; a < W; ++a) s += p.wx[a] * acc[d][a];
    u[d] = s;
  }
}

/// The footprint of a marker whose support crosses the shifted x face: columns 0..split-1 lie in
/// one box, split..W-1 in the next, whose frame is lower by the shift, so each part has its own y
/// rows and weights (as ImmersedBoundary::stencil). Still separable; spread with masked vectors
/// where the CPU has AVX-512VL (markers by the x face: a few per cent of a dense run's).
template <int W>
struct IbSplitFootprint {
  double wx[W], wz[W];    ///< wx carries the normalisation
  double wy[2][W];        ///< y weights of each part
  std::size_t row[2][W];  ///< rows of each part
  std::size_t layer[W];
  std::size_t x0[2];  ///< padded x offset of each part's first column
  int split;          ///< first column of the second part, 1..W-1
};

/// Calls visit(node, weight) for every node of a split footprint.
template <int W, typename Visit>
inline void for_each_node(const IbSplitFootprint<W>& p, Visit visit) {
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b)
      for (int a = 0; a < W; ++a) {
        const int part = a < p.split ? 0 : 1;
        visit(
            p.layer[c] + p.row[part][b] + p.x0[part] + static_cast<std::size_t>(a - part * p.split),
            p.wx[a] * p.wy[part][b] * p.wz[c]);
      }
}

template <int W>
inline void spread_footprint(const IbSplitFootprint<W>& p, const double* f,
                             double* const field[3]) {
#if defined(__AVX512VL__)
  if constexpr (W == 4) {
    // Each row as two masked 4-wide updates, one per box: lane a is node a of the support in
    // both, so part 1's row starts `split` nodes before its first node; masked-out lanes are
    // neither read nor written. Each lane's weight is formed as for_each_node forms it.
    const __mmask8 first = static_cast<__mmask8>((1u << p.split) - 1);
    const auto second = static_cast<__mmask8>(0xF & ~first);
    // Weights, rows and field pointers in locals first, as in spread_footprint(IbFootprint).
    const __m256d wx = _mm256_loadu_pd(p.wx);
    __m256d w0[16], w1[16];
    std::size_t n0[16], n1[16];
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 4; ++b) {
        const __m256d wz = _mm256_set1_pd(p.wz[c]);
        w0[4 * c + b] = _mm256_mul_pd(_mm256_mul_pd(wx, _mm256_set1_pd(p.wy[0][b])), wz);
        w1[4 * c + b] = _mm256_mul_pd(_mm256_mul_pd(wx, _mm256_set1_pd(p.wy[1][b])), wz);
        n0[4 * c + b] = p.layer[c] + p.row[0][b] + p.x0[0];
        n1[4 * c + b] = p.layer[c] + p.row[1][b] + p.x0[1] - static_cast<std::size_t>(p.split);
      }
    for (int d = 0; d < 3; ++d) {
      const __m256d fd = _mm256_set1_pd(f[d]);
      double* const out = field[d];
      for (int r = 0; r < 16; ++r) {
        double* const a = out + n0[r];
        double* const z = out + n1[r];
        _mm256_mask_storeu_pd(a, first,
                              _mm256_fmadd_pd(w0[r], fd, _mm256_maskz_loadu_pd(first, a)));
        _mm256_mask_storeu_pd(z, second,
                              _mm256_fmadd_pd(w1[r], fd, _mm256_maskz_loadu_pd(second, z)));
      }
    }
    return;
  }
#endif
  for_each_node(p, [&](std::size_t n, double w) {
    for (int d = 0; d < 3; ++d) field[d][n] += w * f[d];
  });
}

template <int W>
inline void interpolate_footprint(const IbSplitFootprint<W>& p, const double* const v[3],
                                  double* u) {
#if defined(__AVX512VL__)
  if constexpr (W == 4) {
    // Each row as one 4-wide vector merged from two masked loads, one per box (lane a is node a
    // of the support, as in spread_footprint above); the lanes' y weights are their part's.
    const __mmask8 first = static_cast<__mmask8>((1u << p.split) - 1);
    const auto second = static_cast<__mmask8>(0xF & ~first);
    const __m256d wx = _mm256_loadu_pd(p.wx);
    __m256d a[3] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    for (int c = 0; c < 4; ++c)
      for (int b = 0; b < 4; ++b) {
        const __m256d wy =
            _mm256_mask_blend_pd(second, _mm256_set1_pd(p.wy[0][b]), _mm256_set1_pd(p.wy[1][b]));
        const __m256d w = _mm256_mul_pd(_mm256_mul_pd(wx, wy), _mm256_set1_pd(p.wz[c]));
        const std::size_t n0 = p.layer[c] + p.row[0][b] + p.x0[0];
        const std::size_t n1 =
            p.layer[c] + p.row[1][b] + p.x0[1] - static_cast<std::size_t>(p.split);
        for (int d = 0; d < 3; ++d) {
          const __m256d row =
              _mm256_mask_loadu_pd(_mm256_maskz_loadu_pd(first, v[d] + n0), second, v[d] + n1);
          a[d] = _mm256_fmadd_pd(w, row, a[d]);
        }
      }
    for (int d = 0; d < 3; ++d) {
      alignas(32) double l[4];
      _mm256_store_pd(l, a[d]);
      u[d] = (l[0] + l[1]) + (l[2] + l[3]);
    }
    return;
  }
#endif
  u[0] = u[1] = u[2] = 0.0;
  for_each_node(p, [&](std::size_t n, double w) {
    for (int d = 0; d < 3; ++d) u[d] += w * v[d][n];
  });
}

}  // namespace dld::fluid
