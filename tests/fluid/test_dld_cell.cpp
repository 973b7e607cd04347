// SPDX-License-Identifier: MIT
// The forced DLD unit cell: mass conservation, the shifted periodic boundary against an explicit
// box of columns, and the lateral force controller.
#include <gtest/gtest.h>

#include <cmath>

#include "dld_scene.hpp"
#include "fluid/fluid_solver.hpp"
#include "solver_helpers.hpp"

namespace dld::fluid {
namespace {

TEST(DldCell, MassIsConservedOverTenThousandSteps) {
  // dx = 0.8 um: 40 x 40 x 6 nodes; d = 4.4 um = 5.5 nodes exercises the interpolated shift.
  const Scene scene = testing::dld_scene(0.8, 4.4);
  ASSERT_NE(scene.cell_lu().shift, std::floor(scene.cell_lu().shift));
  FluidSolver s(fluid_config(scene));
  double mass0 = 0;
  {
    std::vector<double> rho, ux, uy, uz;
    s.fields(rho, ux, uy, uz);
    for (std::size_t i = 0; i < rho.size(); ++i) mass0 += rho[i];
    mass0 -= static_cast<double>(rho.size() - s.lattice().fluid_nodes());  // solid nodes hold 1
  }
  for (int i = 0; i < 10000; ++i) s.step();
  EXPECT_GT(s.mean_velocity()[0], 0.0);
  EXPECT_LT(std::abs(s.total_mass() - mass0) / mass0, 1e-12);
}

TEST(DldCell, ShiftedBoundaryEqualsExplicitColumns) {
  // d = lambda/4: four columns with plain periodic x, pillars at x = (k + 1/2) lambda,
  // y = lambda/2 + k d, must reproduce the shifted single cell exactly (same dynamics).
  const Scene scene = testing::dld_scene(0.8, 8.0);
  FluidConfig one = fluid_config(scene);
  one.lateral_control = true;
  FluidConfig four = one;
  const int n = one.domain.nx;
  const double d = one.domain.shift;
  four.domain.nx = 4 * n;
  four.domain.shift = 0.0;
  four.domain.pillars.clear();
  for (int k = 0; k < 4; ++k)
    four.domain.pillars.push_back({(k + 0.5) * n, 0.5 * n + k * d, one.domain.pillars[0].radius});
  FluidSolver a(one), b(four);
  for (int i = 0; i < 600; ++i) {
    a.step();
    b.step();
  }
  double umax = 0, diff = 0;
  const int dn = static_cast<int>(d);
  for (int col = 0; col < 4; ++col)
    for (int k = 0; k < one.domain.nz; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          // Column col of the explicit box is the single cell moved up by col * d.
          const int jb = (j + col * dn) % n;
          if (a.lattice().solid(i, j, k)) {
            EXPECT_TRUE(b.lattice().solid(col * n + i, jb, k));
            continue;
          }
          const Moments ma = a.node_moments(i, j, k);
          const Moments mb = b.node_moments(col * n + i, jb, k);
          umax = std::max(umax, std::abs(ma.ux));
          diff = std::max(
              {diff, std::abs(ma.ux - mb.ux), std::abs(ma.uy - mb.uy), std::abs(ma.uz - mb.uz)});
        }
  EXPECT_GT(umax, 0.0);
  EXPECT_LT(diff / umax, 1e-10) << "max velocity difference " << diff << " of " << umax;
}

TEST(DldCell, LateralControllerZeroesMeanLateralVelocity) {
  const Scene scene = testing::dld_scene(0.8, 6.0);
  FluidSolver s(fluid_config(scene));
  ASSERT_TRUE(s.config().lateral_control);
  testing::run_to_steady(s, 1e-12, 500, 60000);
  const auto u = s.mean_velocity();
  EXPECT_LT(std::abs(u[1]), 1e-6 * u[0]) << "u_y/u_x = " << u[1] / u[0] << " after " << s.steps();
  // The controller must be doing work: the tilted array pushes the flow sideways without it.
  EXPECT_GT(std::abs(s.force_y()), 1e-3 * s.config().force_x);
}

TEST(DldCell, WithoutControllerTheFlowDriftsSideways) {
  const Scene scene = testing::dld_scene(0.8, 6.0);
  FluidConfig c = fluid_config(scene);
  c.lateral_control = false;
  FluidSolver s(c);
  for (int i = 0; i < 3000; ++i) s.step();
  const auto u = s.mean_velocity();
  EXPECT_GT(std::abs(u[1]), 1e-3 * u[0]);
}

}  // namespace
}  // namespace dld::fluid

namespace dld::fluid {
namespace {

TEST(DldCell, PillarLinkFractionFindsTheSurface) {
  Domain d;
  d.nx = d.ny = 40;
  d.nz = 4;
  d.shift = 5.5;
  d.pillars.push_back({20.0, 20.0, 10.0});
  // From (20, 9.3) straight up: the surface at y = 10 is 0.7 of the link away.
  EXPECT_NEAR(d.pillar_link_fraction(20.0, 9.3, 0, 1), 0.7, 1e-12);
  // Diagonal from (29.5, 20.5) towards -x, -y: |(29.5 - t, 20.5 - t) - (20, 20)| = 10.
  const double t = d.pillar_link_fraction(29.5 + 1.0, 20.5, -1, -1);
  EXPECT_NEAR(std::hypot(30.5 - t - 20.0, 20.5 - t - 20.0), 10.0, 1e-12);
  // The image of the pillar one box to the right sits 5.5 higher.
  EXPECT_NEAR(d.pillar_link_fraction(60.0, 9.3 + 5.5, 0, 1), 0.7, 1e-12);
  // A link that misses every pillar.
  EXPECT_EQ(d.pillar_link_fraction(2.5, 2.5, 1, 0), 0.5);
}

TEST(DldCell, BouzidiWallsRunStablyAndStayNearBounceBack) {
  // Interpolated walls change the pillar's effective shape by a fraction of a node: the flow
  // must stay close to the half-way result, and the mass correction keeps the total exact.
  FluidConfig a = fluid_config(testing::dld_scene(0.8, 4.4));
  FluidConfig b = a;
  b.domain.curved_walls = true;
  FluidSolver sa(a), sb(b);
  ASSERT_FALSE(sb.lattice().curved_links().empty());
  const double m0 = sb.total_mass();
  for (int i = 0; i < 3000; ++i) {
    sa.step();
    sb.step();
  }
  const double ua = sa.mean_velocity()[0], ub = sb.mean_velocity()[0];
  EXPECT_TRUE(std::isfinite(ub));
  EXPECT_NEAR(ub / ua, 1.0, 0.05);
  EXPECT_NE(ub, ua);
  EXPECT_LT(std::abs(sb.total_mass() - m0) / m0, 1e-12);
}

}  // namespace
}  // namespace dld::fluid

namespace dld::fluid {
namespace {

TEST(DldCell, KernelVelocityEqualsTheMomentsOfTheNewPopulations) {
  // With a force field the step's kernel stores u for the immersed boundary; it must be the
  // velocity node_moments() recovers from the populations it wrote (Guo: j_post - F/2 = rho u).
  const Scene scene = testing::dld_scene(0.8, 4.4);
  FluidSolver s(fluid_config(scene));
  const auto field = s.force_field();
  const Lattice& L = s.lattice();
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        const std::size_t n = L.index(i, j, k);
        field[0][n] = 1e-4 * std::sin(0.3 * i + 0.1 * k);
        field[1][n] = 1e-4 * std::cos(0.2 * j);
        field[2][n] = 1e-4 * std::sin(0.5 * k + 0.1 * j);
      }
  double worst = 0, largest = 0;
  for (int step = 0; step < 20; ++step) s.step();
  const auto u = s.velocity_field();
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        if (L.solid(i, j, k)) continue;
        const Moments m = s.node_moments(i, j, k);
        const std::size_t n = L.index(i, j, k);
        worst = std::max(
            {worst, std::abs(u[0][n] - m.ux), std::abs(u[1][n] - m.uy), std::abs(u[2][n] - m.uz)});
        largest = std::max(largest, std::abs(m.ux));
      }
  EXPECT_GT(largest, 1e-4);
  EXPECT_LT(worst, 1e-15);
}

}  // namespace
}  // namespace dld::fluid
