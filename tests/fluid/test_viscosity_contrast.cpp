// SPDX-License-Identifier: MIT
// The inside/outside viscosity field: the fluid alone with a layered relaxation field (two-fluid
// Couette flow, analytic), then the indicator built from a closed membrane mesh against the
// analytic ball, across the shifted periodic faces, as the cell moves, and on tie columns.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>
#include <stdexcept>
#include <vector>

#include "fluid/collision/trt.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/viscosity_contrast.hpp"
#include "membrane/sphere_mesh.hpp"
#include "solver_helpers.hpp"

namespace dld::fluid {
namespace {

// Walls at z = 0, H moving at -U, +U; the middle layer (nodes k0..k1) has viscosity ratio r.
// The shear stress is uniform, so u is piecewise linear with slopes in the ratio 1 : 1/r; the
// layer interfaces lie half-way between the last outer and the first inner node.
// Returns the largest |u - exact| / U at steady state.
double layered_couette_error(CollisionKind kind, double U) {
  FluidConfig c;
  c.domain.nx = 3;
  c.domain.ny = 3;
  c.domain.nz = 20;
  const double ratio = 5.0, tau_out = 1.0;
  const double tau_in = 0.5 + ratio * (tau_out - 0.5);
  c.domain.wall_velocity_low = {-U, 0, 0};
  c.domain.wall_velocity_high = {U, 0, 0};
  c.collision = kind;
  c.tau = tau_out;
  FluidSolver s(c);
  const int k0 = 7, k1 = 12;  // inner layer: z in [7, 13]
  RelaxationField& tau = s.relaxation_field();
  for (int k = k0; k <= k1; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) tau.set(s.lattice().index(i, j, k), tau_in);
  // Outer thickness 14 (viscosity 1), inner 6 (viscosity ratio): 2U = sigma (14 + 6 / ratio).
  const double za = k0, zb = k1 + 1.0, H = c.domain.nz;
  const double slope_out = 2 * U / (za + (H - zb) + (zb - za) / ratio);
  auto exact = [&](double z) {
    if (z < za) return -U + slope_out * z;
    if (z < zb) return -U + slope_out * (za + (z - za) / ratio);
    return U - slope_out * (H - z);
  };
  testing::run_to_steady(s, 1e-14, 500, 400000);
  double max_err = 0;
  for (int k = 0; k < c.domain.nz; ++k)
    max_err = std::max(max_err, std::abs(s.node_moments(1, 1, k).ux - exact(k + 0.5)) / U);
  std::printf("%s: layered Couette, ratio %.0f, U %.3g: max |u - exact| / U = %.2e\n",
              kCollisionNames[static_cast<std::size_t>(kind)].data(), ratio, U, max_err);
  return max_err;
}

TEST(ViscosityContrast, LayeredCouetteFlowMatchesTheTwoFluidProfile) {
  // Linear in each layer, so exact up to round-off (as single-fluid Couette flow); the
  // uniform-viscosity answer differs by 24 % of U.
  for (CollisionKind kind : {CollisionKind::kTrt, CollisionKind::kBgk})
    EXPECT_LT(layered_couette_error(kind, 0.01), 1e-11);
}

TEST(ViscosityContrast, MrtLayeredCouetteErrsOnlyAtSecondOrderInTheWallSpeed) {
  // MRT's energy and ghost moments relax at their own rates and their equilibria carry u^2: the
  // relative error goes as U^2 (an interface or wall placement error would not fall with U).
  const double e1 = layered_couette_error(CollisionKind::kMrt, 0.01);
  const double e2 = layered_couette_error(CollisionKind::kMrt, 0.005);
  EXPECT_NEAR(e1 / e2, 4.0, 0.2);
  EXPECT_LT(e1, 1e-5);
}

Domain box(double shift, bool walls_z) {
  Domain d;
  d.nx = 24;
  d.ny = 20;
  d.nz = 16;
  d.shift = shift;
  d.walls_z = walls_z;
  return d;
}

struct Sphere {
  std::vector<double> x;  // markers, 3 per node
  std::vector<std::uint32_t> nodes, faces, face_ids;
};

Sphere sphere(double cx, double cy, double cz, double radius, int subdivisions = 4) {
  const membrane::TriMesh m = membrane::icosphere(subdivisions, radius);
  Sphere s;
  for (int n = 0; n < m.node_count(); ++n)
    for (int a = 0; a < 3; ++a) s.x.push_back(m.nodes(a, n) + (a == 0 ? cx : a == 1 ? cy : cz));
  s.nodes = {static_cast<std::uint32_t>(m.node_count())};
  s.faces = {static_cast<std::uint32_t>(m.face_count())};
  s.face_ids = membrane::face_indices(m);
  return s;
}

// Distance from node (i, j, k) to the centre over all periodic images, in the device frame:
// box b along x is displaced by (b nx, b shift); y and (without walls) z by whole periods.
double image_distance(const Domain& d, int i, int j, int k, const double c[3]) {
  double best = 1e300;
  for (int b = -2; b <= 2; ++b)
    for (int m = -2; m <= 2; ++m)
      for (int l = (d.walls_z ? 0 : -1); l <= (d.walls_z ? 0 : 1); ++l) {
        const double dx = i + 0.5 + b * d.nx - c[0];
        const double dy = j + 0.5 + b * d.shift + m * d.ny - c[1];
        const double dz = k + 0.5 + l * d.nz - c[2];
        best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
  return best;
}

// The icosphere's faces lie inside the sphere by at most the sagitta of its edges (about 0.01 R
// at 4 subdivisions), so nodes farther than that from the surface must be classified exactly.
void expect_ball(const Lattice& L, const ViscosityContrast& vc, const double c[3], double R) {
  const Domain& d = L.domain();
  const std::set<std::size_t> inside(vc.inside_nodes().begin(), vc.inside_nodes().end());
  EXPECT_EQ(inside.size(), vc.inside_nodes().size()) << "a node was marked twice";
  int wrong = 0, shell = 0;
  for (int k = 0; k < d.nz; ++k)
    for (int j = 0; j < d.ny; ++j)
      for (int i = 0; i < d.nx; ++i) {
        const double r = image_distance(d, i, j, k, c);
        if (std::abs(r - R) < 0.06 * R) {
          ++shell;
          continue;
        }
        if ((r < R) != (inside.count(L.index(i, j, k)) == 1)) ++wrong;
      }
  EXPECT_EQ(wrong, 0) << "nodes classified wrongly away from the surface";
  EXPECT_EQ(vc.unpaired_columns(), 0u);
  const double volume = 4.0 / 3.0 * std::numbers::pi * R * R * R;
  EXPECT_NEAR(static_cast<double>(inside.size()) / volume, 1.0, 0.05) << "shell nodes " << shell;
}

TEST(ViscosityContrast, SphereAcrossEveryPeriodicFaceIsTheBall) {
  const Domain d = box(3.4, false);  // fractional shift, periodic z
  const Lattice L(d);
  const double R = 5.0;
  // The centre sits near the x, y and z faces at once; the markers are given one box further
  // along x (x + nx, y + shift), as a membrane that has passed a pillar sends them.
  const double c[3] = {23.3, 18.7, 14.2};
  const Sphere s = sphere(c[0] + d.nx, c[1] + d.shift, c[2], R);
  ViscosityContrast vc(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids);
  RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
  vc.update(s.x, tau);
  expect_ball(L, vc, c, R);
  for (std::size_t n : vc.inside_nodes()) EXPECT_EQ(tau.tau(n), 3.0);
}

TEST(ViscosityContrast, MovingCellLeavesNoInnerViscosityBehind) {
  const Domain d = box(5.0, true);
  const Lattice L(d);
  const double R = 4.0;
  RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
  Sphere s = sphere(6.0, 6.0, 8.0, R);
  ViscosityContrast vc(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids);
  vc.update(s.x, tau);
  const double c[3] = {15.6, 12.2, 8.1};
  s = sphere(c[0], c[1], c[2], R);
  vc.update(s.x, tau);
  expect_ball(L, vc, c, R);
  std::size_t at_inner = 0;
  for (std::size_t n = 0; n < tau.size(); ++n) at_inner += tau.tau(n) == 3.0;
  EXPECT_EQ(at_inner, vc.inside_nodes().size());
}

// The field is updated node by node where a membrane crossed (update() writes only the nodes that
// change side): after every step of a cell moving by small steps, and of one jumping away and
// back, it equals the field a fresh ViscosityContrast builds at those positions.
TEST(ViscosityContrast, UpdatedFieldEqualsAFreshBuildAtEveryStep) {
  const Domain d = box(5.0, true);
  const Lattice L(d);
  RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
  Sphere s = sphere(6.0, 6.0, 8.0, 4.0);
  ViscosityContrast vc(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids);
  std::size_t changed = 0;
  std::vector<double> before(tau.size());
  for (int step = 0; step < 40; ++step) {
    const double t = step < 30 ? 0.137 * step : 12.0 - 0.3 * step;  // slow, then jumps
    s = sphere(6.0 + t, 6.0 + 0.5 * t, 8.0 + 0.05 * t, 4.0 + 0.01 * step);
    for (std::size_t n = 0; n < tau.size(); ++n) before[n] = tau.tau(n);
    vc.update(s.x, tau);
    RelaxationField fresh(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
    ViscosityContrast(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids).update(s.x, fresh);
    for (std::size_t n = 0; n < tau.size(); ++n) {
      ASSERT_EQ(tau.tau(n), fresh.tau(n)) << "node " << n << ", step " << step;
      ASSERT_EQ(tau.plus()[n], fresh.plus()[n]);
      ASSERT_EQ(tau.minus()[n], fresh.minus()[n]);
      changed += tau.tau(n) != before[n];
    }
  }
  EXPECT_GT(changed, 100U);  // the cell did move through nodes
}

TEST(ViscosityContrast, ColumnsThroughVerticesAndEdgesCountOneCrossing) {
  // The column (10.5, 10.5) runs exactly through the icosahedron's edge (0, +-1, t) at its top and
  // bottom, and after subdivision through the vertex that edge's midpoint became, shared by six
  // triangles; the column (10.5, 4.5) grazes the equator at a vertex after subdivision. Each must
  // count once (or, grazing, an even number of times), or the crossings would not pair up.
  const Lattice L(box(0.0, true));
  const double c[3] = {10.5, 10.5, 8.0}, R = 6.0;
  const double t = 0.5 * (1.0 + std::sqrt(5.0));
  for (int subdivisions : {0, 1, 2, 3}) {
    const Sphere s = sphere(c[0], c[1], c[2], R, subdivisions);
    ViscosityContrast vc(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids);
    RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
    vc.update(s.x, tau);
    EXPECT_EQ(vc.unpaired_columns(), 0u) << subdivisions << " subdivisions";
    // Height of the crossing above the centre: the edge's at 0 subdivisions, the pole's after.
    const double h = subdivisions == 0 ? R * t / std::sqrt(1.0 + t * t) : R;
    for (int k = 0; k < 16; ++k) {
      const bool in = std::abs(k + 0.5 - c[2]) < h;
      EXPECT_EQ(tau.tau(L.index(10, 10, k)), in ? 3.0 : 1.0)
          << "k " << k << ", " << subdivisions << " subdivisions";
    }
  }
}

TEST(ViscosityContrast, CellAcrossTheXFaceGetsTheFieldOfTheSameCellInside) {
  // A cell inside the box is classified triangle-parallel; the triangles of one across the x face
  // that reach past it are walked box by box. With coordinates on a 2^-12 grid, moving the cell by
  // whole nodes moves every edge function and crossing height exactly, so the two paths must give
  // the same nodes, moved: 9 nodes in x (no shift, so x wraps alone), across the vertex and edge
  // ties of icospheres centred on column centres and lattice nodes.
  const Domain d = box(0.0, true);
  const Lattice L(d);
  for (const double cy : {10.0, 10.5, 9.73}) {
    for (const int subdivisions : {1, 2, 3}) {
      Sphere across = sphere(1.5, cy, 8.0, 5.0, subdivisions);
      for (double& v : across.x) v = std::round(v * 4096.0) / 4096.0;
      Sphere inside = across;
      for (std::size_t m = 0; m < inside.x.size(); m += 3) inside.x[m] += 9.0;
      RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
      ViscosityContrast a(L, 1.0, 3.0, across.nodes, across.faces, across.face_ids);
      ViscosityContrast b(L, 1.0, 3.0, inside.nodes, inside.faces, inside.face_ids);
      a.update(across.x, tau);
      b.update(inside.x, tau);
      std::set<std::size_t> moved;
      for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
          for (int i = 0; i < d.nx; ++i)
            if (std::count(a.inside_nodes().begin(), a.inside_nodes().end(), L.index(i, j, k)))
              moved.insert(L.index((i + 9) % d.nx, j, k));
      const std::set<std::size_t> got(b.inside_nodes().begin(), b.inside_nodes().end());
      EXPECT_GT(moved.size(), 300u);
      EXPECT_EQ(got, moved) << "y " << cy << ", " << subdivisions << " subdivisions";
      EXPECT_EQ(a.unpaired_columns() + b.unpaired_columns(), 0u);
    }
  }
}

TEST(ViscosityContrast, SolidNodesKeepTheirRelaxationTime) {
  Domain d = box(0.0, true);
  d.pillars.push_back({12.0, 10.0, 3.0});
  const Lattice L(d);
  const Sphere s = sphere(12.0, 10.0, 8.0, 5.0);  // around the pillar: the overlap is solid
  ViscosityContrast vc(L, 1.0, 3.0, s.nodes, s.faces, s.face_ids);
  RelaxationField tau(L.padded_size(), 1.0, &Trt::rates, 3.0 / 16.0, false);
  vc.update(s.x, tau);
  EXPECT_GT(vc.inside_nodes().size(), 0u);
  for (std::size_t n : vc.inside_nodes()) EXPECT_EQ(L.solid_mask()[n], 0);
}

TEST(ViscosityContrast, CellsWithoutSurfaceAreRefused) {
  const Lattice L(box(0.0, true));
  const std::vector<std::uint32_t> nodes{1, 1}, faces{0, 0}, ids;
  EXPECT_THROW(ViscosityContrast(L, 1.0, 3.0, nodes, faces, ids), std::invalid_argument);
}

}  // namespace
}  // namespace dld::fluid
