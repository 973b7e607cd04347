// SPDX-License-Identifier: MIT
// Immersed-boundary kernels, spreading and interpolation, including across the shifted x face.
#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "fluid/immersed_boundary.hpp"
#include "tests/fluid/ib_test_domain.hpp"

namespace dld::fluid {
namespace {

using test::markers_everywhere;
using test::test_domain;

const IbKernel kKernels[] = {IbKernel::kPeskin2, IbKernel::kPeskin3, IbKernel::kPeskin4};

/// Markers everywhere in the test domain (shift 3.4) with forces 0.1, a force field to spread
/// them into and a random velocity field (uniform in [-1, 1)) to interpolate.
struct MarkersAndVelocity {
  MarkersAndVelocity(int markers, unsigned seed, unsigned velocity_seed)
      : L(test_domain(3.4)),
        n(L.padded_size()),
        pos(markers_everywhere(L, markers, seed)),
        frc(pos.size(), 0.1),
        field(3 * n),
        vel(3 * n),
        v{vel.data(), vel.data() + n, vel.data() + 2 * n} {
    std::mt19937 rng(velocity_seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double& x : vel) x = u(rng);
  }
  std::array<double*, 3> force_field() {
    return {field.data(), field.data() + n, field.data() + 2 * n};
  }
  Lattice L;
  std::size_t n;
  std::vector<double> pos, frc, field, vel;
  std::array<const double*, 3> v;
};

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

TEST(ImmersedBoundary, SpreadingConservesTotalForceEverywhere) {
  // Markers anywhere: across the shifted x face (fractional shift), the y face, next to the
  // walls and the pillar; the solid nodes dropped from a stencil must not lose force.
  const Lattice L(test_domain(3.4));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(-30.0, 50.0), uy(-25.0, 45.0), uz(0.3, 9.7),
      uf(-1.0, 1.0);
  std::vector<double> pos, frc;
  while (pos.size() < std::size_t{3} * 400) {
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
    if (k == IbKernel::kPeskin4) {  // every kind of kept footprint is exercised
      std::size_t separable = 0, split = 0;
      for (std::size_t m = 0; m < pos.size() / 3; ++m) {
        IbFootprint<4> fp;
        IbSplitFootprint<4> sp;
        if (ib.footprint<4>(&pos[3 * m], fp))
          ++separable;
        else if (ib.split_footprint<4>(&pos[3 * m], sp))
          ++split;
      }
      EXPECT_GT(separable, 0U);
      EXPECT_GT(split, 0U);
      EXPECT_GT(pos.size() / 3 - separable - split, 0U);
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
      // After a spread at the same positions, interpolation reads the kept footprints (separable,
      // across the x face, and the stencils near solids): the same bits as computing them afresh.
      const ImmersedBoundary fresh(L, k);
      std::vector<double> fresh_u(pos.size());
      fresh.interpolate(pos, {vel.data(), vel.data() + n, vel.data() + 2 * n}, fresh_u);
      EXPECT_EQ(fresh_u, got_u) << static_cast<int>(k) << "-point, " << threads << " threads";
    }
    omp_set_num_threads(1);
  }
}

TEST(ImmersedBoundary, InterpolationAtTheSpreadIsInterpolationAtItsPositions) {
  // [coupling] spread_held: the velocity at the last spread's positions, whatever the markers did
  // since, with every kernel; an error before any spread.
  MarkersAndVelocity scene(500, 9, 4);
  const Lattice& L = scene.L;
  const auto& pos = scene.pos;
  const auto& v = scene.v;
  for (IbKernel k : kKernels) {
    const ImmersedBoundary ib(L, k);
    std::vector<double> held(pos.size()), want(pos.size()), moved_u(pos.size());
    EXPECT_THROW(ib.interpolate_at_spread(v, held), std::logic_error);
    ib.spread(pos, scene.frc, scene.force_field());
    auto moved = pos;
    for (double& x : moved) x += 0.3;  // the markers move on; the weights stay where they were
    ib.interpolate(moved, v, moved_u);
    ib.interpolate_at_spread(v, held);
    const ImmersedBoundary fresh(L, k);
    fresh.interpolate(pos, v, want);
    EXPECT_EQ(held, want) << static_cast<int>(k) << "-point";
    EXPECT_NE(held, moved_u) << static_cast<int>(k) << "-point";
  }
}

TEST(ImmersedBoundary, InterpolationAtMovedMarkersIsMarkerByMarkerBitForBit) {
  // A held step interpolates at markers moved since the last spread, in batches and in that
  // spread's order: each velocity is the one marker's own footprint sum, bit for bit, with or
  // without a spread before and with 1 or 2 threads.
  MarkersAndVelocity scene(2000, 12, 6);
  const Lattice& L = scene.L;
  const auto& pos = scene.pos;
  const auto& v = scene.v;
  auto moved = pos;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  for (double& x : moved) x += u(rng);
  const ImmersedBoundary ib(L, IbKernel::kPeskin4);
  std::vector<double> want(pos.size());
  std::size_t separable = 0;
  for (std::size_t m = 0; m < pos.size() / 3; ++m) {
    IbFootprint<4> fp;
    if (!ib.footprint<4>(&moved[3 * m], fp)) continue;  // the others: the node-list test above
    interpolate_footprint(fp, v.data(), &want[3 * m]);
    ++separable;
  }
  ASSERT_GT(separable, pos.size() / 6);
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    const ImmersedBoundary fresh(L, IbKernel::kPeskin4);
    std::vector<double> got(pos.size()), got_fresh(pos.size());
    ib.spread(pos, scene.frc, scene.force_field());
    ib.interpolate(moved, v, got);
    fresh.interpolate(moved, v, got_fresh);
    EXPECT_EQ(got, got_fresh) << threads << " threads";
    for (std::size_t m = 0; m < pos.size() / 3; ++m) {
      IbFootprint<4> fp;
      if (!ib.footprint<4>(&moved[3 * m], fp)) continue;
      for (int a = 0; a < 3; ++a)
        ASSERT_EQ(got[3 * m + a], want[3 * m + a]) << "marker " << m << ", " << threads;
    }
  }
  omp_set_num_threads(1);
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
