// SPDX-License-Identifier: MIT
// Immersed-boundary kernels, spreading and interpolation, including across the shifted x face.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <random>
#include <vector>

#include "fluid/ib_axis_batch.hpp"
#include "fluid/immersed_boundary.hpp"

namespace dld::fluid {
namespace {

const IbKernel kKernels[] = {IbKernel::kPeskin2, IbKernel::kPeskin3, IbKernel::kPeskin4};

TEST(IbKernel, PartitionOfUnityAndZeroFirstMoment) {
  for (IbKernel k : kKernels)
    for (double x = 0.0; x < 1.0; x += 0.0625) {
      double sum = 0, first = 0;
      for (int j = -4; j <= 4; ++j) {
        sum += phi(k, j - x);
        first += (j - x) * phi(k, j - x);
      }
      EXPECT_NEAR(sum, 1.0, 1e-14) << static_cast<int>(k) << "-point at " << x;
      EXPECT_NEAR(first, 0.0, 1e-14) << static_cast<int>(k) << "-point at " << x;
    }
}

TEST(IbKernel, ZeroOutsideSupport) {
  for (IbKernel k : kKernels) {
    EXPECT_EQ(phi(k, half_width(k)), 0.0);
    EXPECT_EQ(phi(k, -half_width(k) - 0.3), 0.0);
    EXPECT_GT(phi(k, half_width(k) - 0.05), 0.0);
  }
}

Domain test_domain(double shift) {
  Domain d;
  d.nx = 24;
  d.ny = 20;
  d.nz = 10;
  d.shift = shift;
  d.walls_z = true;
  d.pillars.push_back({12.0, 10.0, 4.0});
  return d;
}

TEST(ImmersedBoundary, SpreadingConservesTotalForceEverywhere) {
  // Markers anywhere: across the shifted x face (fractional shift), the y face, next to the
  // walls and the pillar; the solid nodes dropped from a stencil must not lose force.
  const Lattice L(test_domain(3.4));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-30.0, 50.0), uy(-25.0, 45.0), uz(0.3, 9.7),
      uf(-1.0, 1.0);
  std::vector<double> pos, frc;
  while (pos.size() < 3 * 400) {
    const double p[3] = {ux(rng), uy(rng), uz(rng)};
    // Keep markers out of the pillar itself (there the fluid has no node to receive force).
    double x = std::fmod(std::fmod(p[0], 24.0) + 24.0, 24.0);
    double y = p[1] - std::floor(p[0] / 24.0) * 3.4;
    if (L.domain().in_pillar(x, y)) continue;
    pos.insert(pos.end(), p, p + 3);
    frc.insert(frc.end(), {uf(rng), uf(rng), uf(rng)});
  }
  for (IbKernel k : kKernels) {
    const ImmersedBoundary ib(L, k);
    std::vector<double> field(3 * L.padded_size());
    const std::size_t n = L.padded_size();
    ib.spread(pos, frc, {field.data(), field.data() + n, field.data() + 2 * n});
    double want[3] = {0, 0, 0}, got[3] = {0, 0, 0};
    for (std::size_t m = 0; m < frc.size(); ++m) want[m % 3] += frc[m];
    for (int a = 0; a < 3; ++a)
      for (std::size_t s = 0; s < n; ++s) {
        if (L.solid_mask()[s]) {
          EXPECT_EQ(field[a * n + s], 0.0);
        }
        got[a] += field[a * n + s];
      }
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(got[a], want[a], 1e-12) << static_cast<int>(k);
  }
}

// A velocity field on all nodes: u = (a + b z, c y, e z) with y the box coordinate.
std::vector<double> linear_field(const Lattice& L, double a, double b, double c, double e) {
  const std::size_t n = L.padded_size();
  std::vector<double> u(3 * n, 0.0);
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        const std::size_t s = L.index(i, j, k);
        u[s] = a + b * (k + 0.5);
        u[n + s] = c * (j + 0.5);
        u[2 * n + s] = e * (k + 0.5);
      }
  return u;
}

TEST(ImmersedBoundary, InterpolatesLinearFieldsExactlyInTheBulk) {
  Domain d = test_domain(3.4);
  d.pillars.clear();
  const Lattice L(d);
  const auto u = linear_field(L, 0.3, 0.02, 0.01, -0.005);
  const std::size_t n = L.padded_size();
  for (IbKernel k : kKernels) {
    const ImmersedBoundary ib(L, k);
    // Away from the walls (z) and from the periodic faces (x, y) by more than the kernel reach.
    const std::vector<double> pos{8.3, 7.7, 4.1, 12.0, 12.5, 5.0, 15.61, 9.02, 3.37};
    std::vector<double> out(pos.size());
    ib.interpolate(pos, {u.data(), u.data() + n, u.data() + 2 * n}, out);
    for (std::size_t m = 0; m < 3; ++m) {
      EXPECT_NEAR(out[3 * m], 0.3 + 0.02 * pos[3 * m + 2], 1e-14);
      EXPECT_NEAR(out[3 * m + 1], 0.01 * pos[3 * m + 1], 1e-14);
      EXPECT_NEAR(out[3 * m + 2], -0.005 * pos[3 * m + 2], 1e-14);
    }
  }
}

TEST(ImmersedBoundary, ShiftedFaceMovesTheWrappedColumnsByTheShift) {
  // A marker at the left face: columns beyond x = 0 are the right end of the box seen from the
  // previous box, whose y coordinate is higher by d. With u_y = c y_box, the exact interpolant is
  // c (Y + d W_left), W_left the x weight of the wrapped columns. Fractional d checks the
  // sub-node shift; u_x and u_z, linear in z only, must stay exact across the face.
  Domain d = test_domain(3.4);
  d.pillars.clear();
  const Lattice L(d);
  const double c = 0.01;
  const auto u = linear_field(L, 0.3, 0.02, c, -0.005);
  const std::size_t n = L.padded_size();
  for (IbKernel k : kKernels) {
    const ImmersedBoundary ib(L, k);
    for (double X : {0.2, 0.9, 23.4, 23.7}) {
      const double Y = 9.3, Z = 4.6;
      double w_other = 0;  // x weight of columns in the neighbouring box
      for (int i = -3; i <= 26; ++i)
        if (i < 0 || i >= 24) w_other += phi(k, i + 0.5 - X);
      const double sign = X < 12 ? +1.0 : -1.0;  // left face: frame higher by d; right: lower
      const std::vector<double> pos{X, Y, Z};
      std::vector<double> out(3);
      ib.interpolate(pos, {u.data(), u.data() + n, u.data() + 2 * n}, out);
      if (X == 0.2 || X == 23.7) {
        EXPECT_GT(w_other, 0.0);  // every kernel reaches across
      }
      EXPECT_NEAR(out[1], c * (Y + sign * 3.4 * w_other), 1e-14) << "X " << X;
      EXPECT_NEAR(out[0], 0.3 + 0.02 * Z, 1e-14);
      EXPECT_NEAR(out[2], -0.005 * Z, 1e-14);
    }
  }
}

TEST(ImmersedBoundary, MarkerFoldedFromAnotherBoxSeesTheSameNodes) {
  // The same material point given in the next box's coordinates (x + nx, y + d).
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  IbStencil a, b;
  const double p[3] = {5.3, 3.1, 2.2}, q[3] = {5.3 + 24.0, 3.1 + 3.4, 2.2};
  ASSERT_TRUE(ib.stencil(p, a));
  ASSERT_TRUE(ib.stencil(q, b));
  ASSERT_EQ(a.count, b.count);
  for (int i = 0; i < a.count; ++i) {
    EXPECT_EQ(a.node[i], b.node[i]);
    EXPECT_NEAR(a.weight[i], b.weight[i], 1e-14);
  }
}

TEST(ImmersedBoundary, MarkerSeveralBoxesAwayInYSeesTheSameNodes) {
  // y is periodic: a marker given two or three boxes up or down (as an unwrapped membrane can be)
  // must touch the nodes of its image in the box, not nodes of another z layer.
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  const double p[3] = {5.3, 0.6, 2.2};
  IbStencil a;
  ASSERT_TRUE(ib.stencil(p, a));
  for (double boxes : {-3.0, -2.0, 2.0, 3.0}) {
    IbStencil b;
    const double q[3] = {p[0], p[1] + boxes * 20.0, p[2]};
    ASSERT_TRUE(ib.stencil(q, b));
    ASSERT_EQ(a.count, b.count) << boxes;
    for (int i = 0; i < a.count; ++i) {
      EXPECT_EQ(a.node[i], b.node[i]) << boxes;
      EXPECT_NEAR(a.weight[i], b.weight[i], 1e-14) << boxes;
    }
  }
}

TEST(ImmersedBoundary, SpreadAndInterpolateAreAdjoint) {
  // sum_m U_m . F_m = sum_nodes u . f: the power the markers put in is the power the fluid gets.
  const Lattice L(test_domain(2.0));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  const std::size_t n = L.padded_size();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> r(-1, 1);
  std::vector<double> u(3 * n);
  for (auto& v : u) v = r(rng);
  const std::vector<double> pos{1.0, 2.0, 1.2, 23.5, 19.6, 8.8, 4.0, 15.0, 5.0};
  const std::vector<double> frc{0.3, -0.2, 0.1, 1.0, 0.5, -0.7, -0.4, 0.2, 0.9};
  std::vector<double> field(3 * n), um(9);
  ib.spread(pos, frc, {field.data(), field.data() + n, field.data() + 2 * n});
  ib.interpolate(pos, {u.data(), u.data() + n, u.data() + 2 * n}, um);
  double pm = 0, pf = 0;
  for (int i = 0; i < 9; ++i) pm += um[i] * frc[i];
  for (std::size_t s = 0; s < 3 * n; ++s) pf += u[s] * field[s];
  EXPECT_NEAR(pm, pf, 1e-13);
}

TEST(ImmersedBoundary, SpreadingWithTwoThreadsEqualsOneThread) {
  // Per-thread force fields are added up after spreading: the result must not depend on it.
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  const std::size_t n = L.padded_size();
  std::vector<double> pos, frc;
  for (int m = 0; m < 300; ++m) {
    pos.insert(pos.end(), {0.08 * m, 1.0 + 0.01 * m, 2.0 + 0.02 * m});  // below the pillar
    frc.insert(frc.end(), {std::sin(m * 1.0), std::cos(m * 0.7), 0.1});
  }
  std::vector<double> one(3 * n), two(3 * n);
  omp_set_num_threads(1);
  ib.spread(pos, frc, {one.data(), one.data() + n, one.data() + 2 * n});
  omp_set_num_threads(2);
  ib.spread(pos, frc, {two.data(), two.data() + n, two.data() + 2 * n});
  omp_set_num_threads(1);
  double diff = 0, size = 0;
  for (std::size_t i = 0; i < 3 * n; ++i) {
    diff = std::max(diff, std::abs(one[i] - two[i]));
    size = std::max(size, std::abs(one[i]));
  }
  EXPECT_GT(size, 0.0);
  EXPECT_LT(diff, 1e-14 * size);
}

/// Markers anywhere outside the pillar of test_domain(shift): across both faces, by the walls.
std::vector<double> markers_everywhere(const Lattice& L, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-30.0, 50.0), uy(-25.0, 45.0), uz(0.3, 9.7);
  std::vector<double> pos;
  while (pos.size() < 3 * static_cast<std::size_t>(count)) {
    const double p[3] = {ux(rng), uy(rng), uz(rng)};
    const double x = std::fmod(std::fmod(p[0], 24.0) + 24.0, 24.0);
    const double y = p[1] - std::floor(p[0] / 24.0) * L.domain().shift;
    if (!L.domain().in_pillar(x, y)) pos.insert(pos.end(), p, p + 3);
  }
  return pos;
}

/// Every node of a footprint with a non-zero weight is a node of stencil() with the same weight,
/// and there are as many.
template <typename Footprint, typename NodeWeight>
void expect_same_nodes(const IbStencil& s, int W, NodeWeight node_weight, std::size_t m) {
  int weighted = 0;  // z layers beyond a wall have weight zero in the footprint
  for (int c = 0; c < W; ++c)
    for (int b = 0; b < W; ++b)
      for (int a = 0; a < W; ++a) {
        const auto [node, w] = node_weight(a, b, c);
        if (w == 0.0) continue;
        ++weighted;
        int found = -1;
        for (int r = 0; r < s.count; ++r)
          if (s.node[r] == node) found = r;
        ASSERT_GE(found, 0) << "node " << node << " of marker " << m;
        EXPECT_NEAR(w, s.weight[found], 1e-15) << W << "-point, marker " << m;
      }
  EXPECT_EQ(weighted, s.count) << "the footprint's nodes are the stencil's, marker " << m;
}

template <int W>
void expect_footprint_is_stencil(const Lattice& L, IbKernel k, const std::vector<double>& pos) {
  const ImmersedBoundary ib(L, k);
  int separable = 0, split = 0, listed = 0;
  for (std::size_t m = 0; m < pos.size() / 3; ++m) {
    IbFootprint<W> fp;
    IbSplitFootprint<W> sp;
    IbStencil s;
    ASSERT_TRUE(ib.stencil(&pos[3 * m], s));
    if (ib.footprint<W>(&pos[3 * m], fp)) {
      ++separable;
      expect_same_nodes<IbFootprint<W>>(
          s, W,
          [&](int a, int b, int c) {
            return std::pair{fp.layer[c] + fp.row[b] + fp.x0 + a, fp.wx[a] * fp.wy[b] * fp.wz[c]};
          },
          m);
    } else if (ib.split_footprint<W>(&pos[3 * m], sp)) {
      ++split;
      expect_same_nodes<IbSplitFootprint<W>>(
          s, W,
          [&](int a, int b, int c) {
            const int part = a < sp.split ? 0 : 1;
            return std::pair{sp.layer[c] + sp.row[part][b] + sp.x0[part] +
                                 static_cast<std::size_t>(a - part * sp.split),
                             sp.wx[a] * sp.wy[part][b] * sp.wz[c]};
          },
          m);
    } else {
      ++listed;
    }
  }
  EXPECT_GT(separable, 100) << W << "-point";
  EXPECT_GT(split, 10) << W << "-point: markers across the shifted x face";
  EXPECT_GT(listed, 10) << W << "-point: markers by the pillar";
}

TEST(ImmersedBoundary, SeparableFootprintHasTheStencilsNodesAndWeights) {
  const Lattice L(test_domain(3.4));
  const auto pos = markers_everywhere(L, 1000, 11);
  expect_footprint_is_stencil<2>(L, IbKernel::kPeskin2, pos);
  expect_footprint_is_stencil<3>(L, IbKernel::kPeskin3, pos);
  expect_footprint_is_stencil<4>(L, IbKernel::kPeskin4, pos);
}

// The SIMD batch of axis weights (fluid/ib_axis_batch.hpp) gives footprint<4>()'s footprint bit
// for bit, also for markers folded from other boxes, by the walls and refused ones (x face,
// pillar, not finite).
TEST(ImmersedBoundary, BatchedFootprintEqualsTheMarkerByMarkerOneBitForBit) {
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  auto pos = markers_everywhere(L, 1000, 23);
  for (std::size_t m = 0; m < 100; ++m)
    pos[3 * m] += static_cast<double>(m % 5) * L.nx() - 2.0 * L.nx();
  pos[3 * 7] = std::nan("");
  pos[3 * 8 + 2] = INFINITY;
  const std::size_t markers = pos.size() / 3;
  std::vector<std::uint32_t> index(markers);
  for (std::size_t m = 0; m < markers; ++m) index[m] = static_cast<std::uint32_t>(markers - 1 - m);
  int separable = 0, refused = 0;
  for (std::size_t q0 = 0; q0 < markers; q0 += kIbBatch) {
    const int n = static_cast<int>(std::min<std::size_t>(kIbBatch, markers - q0));
    Peskin4AxisBatch axes;
    peskin4_axis_batch(pos.data(), &index[q0], n, L.nx(), L.domain().shift, axes);
    for (int l = 0; l < n; ++l) {
      const double* p = &pos[3 * index[q0 + static_cast<std::size_t>(l)]];
      IbFootprint<4> a, b;
      const bool one = ib.footprint<4>(p, a), batch = ib.batched_footprint(axes, l, p, b);
      ASSERT_EQ(one, batch) << "marker " << index[q0 + static_cast<std::size_t>(l)];
      if (!one) {
        ++refused;
        continue;
      }
      ++separable;
      EXPECT_EQ(a.x0, b.x0);
      for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(a.wx[k], b.wx[k]);  // exact equality: the same bits
        EXPECT_EQ(a.wy[k], b.wy[k]);
        EXPECT_EQ(a.wz[k], b.wz[k]);
        EXPECT_EQ(a.row[k], b.row[k]);
        EXPECT_EQ(a.layer[k], b.layer[k]);
      }
    }
  }
  EXPECT_GT(separable, 500);
  EXPECT_GT(refused, 20);
}

// A footprint across the shifted x face spreads (with masked vectors where the CPU has them) the
// same bits as the node-by-node loop over its nodes.
TEST(ImmersedBoundary, SplitFootprintSpreadsTheNodeLoopsBits) {
  const Lattice L(test_domain(3.4));
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  const auto pos = markers_everywhere(L, 2000, 31);
  const std::size_t n = L.padded_size();
  std::vector<double> a(3 * n, 0.0), b(3 * n, 0.0);
  double* const fa[3] = {a.data(), a.data() + n, a.data() + 2 * n};
  double* const fb[3] = {b.data(), b.data() + n, b.data() + 2 * n};
  int split = 0;
  for (std::size_t m = 0; m < pos.size() / 3; ++m) {
    IbSplitFootprint<4> sp;
    if (!ib.split_footprint<4>(&pos[3 * m], sp)) continue;
    ++split;
    const double f[3] = {0.3 + 1e-3 * static_cast<double>(m), -0.7, 1.1};
    spread_footprint(sp, f, fa);
    for_each_node(sp, [&](std::size_t node, double w) {
      for (int d = 0; d < 3; ++d) fb[d][node] += w * f[d];
    });
  }
  EXPECT_GT(split, 10);
  EXPECT_EQ(a, b);  // every node, bit for bit; nothing outside the footprints is touched
}

// spread() and interpolate() (separable footprints, x slabs per thread) against the plain sums
// over stencil()'s node lists, for 1 and 2 threads: equal to round-off.
TEST(ImmersedBoundary, SpreadAndInterpolateEqualTheNodeListSums) {
  const Lattice L(test_domain(3.4));
  const std::size_t n = L.padded_size();
  const auto pos = markers_everywhere(L, 2000, 5);
  std::vector<double> frc(pos.size()), vel(3 * n);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& f : frc) f = u(rng);
  for (double& v : vel) v = u(rng);
  for (IbKernel k : kKernels) {
    const ImmersedBoundary ib(L, k);
    std::vector<double> want(3 * n, 0.0), want_u(pos.size(), 0.0);
    for (std::size_t m = 0; m < pos.size() / 3; ++m) {
      IbStencil s;
      ASSERT_TRUE(ib.stencil(&pos[3 * m], s));
      for (int q = 0; q < s.count; ++q)
        for (int a = 0; a < 3; ++a) {
          want[a * n + s.node[q]] += s.weight[q] * frc[3 * m + a];
          want_u[3 * m + a] += s.weight[q] * vel[a * n + s.node[q]];
        }
    }
    for (int threads : {1, 2}) {
      omp_set_num_threads(threads);
      std::vector<double> got(3 * n, 7.0), got_u(pos.size());
      ib.spread(pos, frc, {got.data(), got.data() + n, got.data() + 2 * n});
      ib.interpolate(pos, {vel.data(), vel.data() + n, vel.data() + 2 * n}, got_u);
      double df = 0, du = 0;
      for (std::size_t i = 0; i < got.size(); ++i) df = std::max(df, std::abs(got[i] - want[i]));
      for (std::size_t i = 0; i < got_u.size(); ++i)
        du = std::max(du, std::abs(got_u[i] - want_u[i]));
      EXPECT_LT(df, 1e-14) << static_cast<int>(k) << "-point, " << threads << " threads";
      EXPECT_LT(du, 1e-14) << static_cast<int>(k) << "-point, " << threads << " threads";
    }
    omp_set_num_threads(1);
  }
}

TEST(ImmersedBoundary, MarkerInsideThePillarIsReported) {
  const Lattice L(test_domain(0.0));
  const ImmersedBoundary ib(L, IbKernel::kPeskin2);
  const std::vector<double> pos{12.0, 10.0, 5.0}, frc{1, 0, 0};
  std::vector<double> field(3 * L.padded_size());
  const std::size_t n = L.padded_size();
  EXPECT_THROW(ib.spread(pos, frc, {field.data(), field.data() + n, field.data() + 2 * n}),
               std::runtime_error);
}

}  // namespace
}  // namespace dld::fluid
