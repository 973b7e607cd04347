// SPDX-License-Identifier: MIT
// The in-place (AA) update (FluidConfig::in_place, fluid/population_view.hpp) is the pull update
// with another memory layout: the same arithmetic on the same values, so every moment, every flow
// sum and the pull-layout populations agree bit for bit, step after step, whatever the boundaries
// (fractional shift, pillar with half-way or interpolated bounce-back, moving z walls, periodic
// z), the fields (force, relaxation time) and the collision; a restart from the pull-layout copy
// continues the run exactly.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "fluid/fluid_solver.hpp"

namespace dld::fluid {
namespace {

struct Case {
  const char* name;
  double shift;
  bool walls_z, curved, moving_walls, fields;
  CollisionKind collision;
};

FluidConfig config_of(const Case& c, bool in_place) {
  FluidConfig f;
  f.domain.nx = 24;
  f.domain.ny = 20;
  f.domain.nz = 10;
  f.domain.shift = c.shift;
  f.domain.walls_z = c.walls_z;
  f.domain.curved_walls = c.curved;
  f.domain.pillars.push_back({12.0, 10.0, 4.3});
  if (c.moving_walls) f.domain.wall_velocity_high = {0.01, -0.004, 0.0};
  f.collision = c.collision;
  f.tau = 0.8;
  f.force_x = 2e-5;
  f.force_y = 3e-6;
  f.lateral_control = c.walls_z;
  f.huge_pages = false;
  f.in_place = in_place;
  return f;
}

/// Fields that a coupled run would set: a force near a "cell" and a patch of higher tau.
void set_fields(FluidSolver& s, const Case& c) {
  if (!c.fields) return;
  const Lattice& L = s.lattice();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-5, 1e-5);
  const auto force = s.force_field();
  RelaxationField& tau = s.relaxation_field();
  for (int k = 2; k < 7; ++k)
    for (int j = 1; j < 8; ++j)
      for (int i = 1; i < 22; ++i) {
        const std::size_t node = L.index(i, j, k);
        if (L.solid(i, j, k)) continue;
        for (int a = 0; a < 3; ++a) force[a][node] = u(rng);
        if (i % 3 == 0) tau.set(node, 2.5);
      }
}

void expect_same_flow(FluidSolver& pull, FluidSolver& aa, int step) {
  const Lattice& L = pull.lattice();
  ASSERT_EQ(pull.sums().mass, aa.sums().mass) << "step " << step;
  ASSERT_EQ(pull.sums().momentum_x, aa.sums().momentum_x) << "step " << step;
  ASSERT_EQ(pull.sums().momentum_y, aa.sums().momentum_y) << "step " << step;
  ASSERT_EQ(pull.force_y(), aa.force_y()) << "step " << step;
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        if (L.solid(i, j, k)) continue;
        const Moments a = pull.node_moments(i, j, k), b = aa.node_moments(i, j, k);
        ASSERT_EQ(a.rho, b.rho) << "node " << i << " " << j << " " << k << ", step " << step;
        ASSERT_EQ(a.ux, b.ux) << "node " << i << " " << j << " " << k << ", step " << step;
        ASSERT_EQ(a.uy, b.uy);
        ASSERT_EQ(a.uz, b.uz);
      }
  const auto va = pull.velocity_field(), vb = aa.velocity_field();
  for (std::size_t s = 0; s < L.padded_size(); ++s)
    for (int a = 0; a < 3; ++a) ASSERT_EQ(va[a][s], vb[a][s]) << "velocity " << s;
}

/// The pull-layout populations at fluid nodes (ghost and solid slots are refilled before use).
std::vector<double> fluid_populations(const FluidSolver& s) {
  const Lattice& L = s.lattice();
  const std::size_t n = L.padded_size();
  std::vector<double> all = s.pull_populations(), out;
  for (int q = 0; q < D3Q19::q; ++q)
    for (int k = 0; k < L.nz(); ++k)
      for (int j = 0; j < L.ny(); ++j)
        for (int i = 0; i < L.nx(); ++i)
          if (!L.solid(i, j, k)) out.push_back(all[q * n + L.index(i, j, k)]);
  return out;
}

TEST(InPlace, EqualsThePullUpdateBitForBitOnEveryKindOfBoundary) {
  const Case cases[] = {
      {"fractional shift, walls, fields", 3.4, true, false, false, true, CollisionKind::kTrt},
      {"interpolated pillar, moving wall", 3.4, true, true, true, true, CollisionKind::kTrt},
      {"whole shift, periodic z, MRT", 5.0, false, false, false, true, CollisionKind::kMrt},
      {"BGK without fields", 2.7, true, true, false, false, CollisionKind::kBgk},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    FluidSolver pull(config_of(c, false)), aa(config_of(c, true));
    set_fields(pull, c);
    set_fields(aa, c);
    for (int step = 1; step <= 25; ++step) {  // odd: ends in the shifted layout
      pull.step();
      aa.step();
      if (step % 4 == 1 || step == 25) expect_same_flow(pull, aa, step);
    }
    // Fields and ghosts are part of the pull copy only at fluid nodes.
    EXPECT_EQ(fluid_populations(pull), fluid_populations(aa));
  }
}

TEST(InPlace, RestartFromThePullCopyContinuesExactlyInEitherLayout) {
  const Case c{
      "fractional shift, walls, fields", 3.4, true, true, false, true, CollisionKind::kTrt};
  for (int stop : {12, 13}) {  // swapped and shifted layouts at the restart
    FluidSolver straight(config_of(c, true)), first(config_of(c, true));
    set_fields(straight, c);
    set_fields(first, c);
    for (int step = 0; step < stop; ++step) first.step();
    FluidSolver resumed(config_of(c, true));
    set_fields(resumed, c);
    resumed.restore(first.pull_populations(), first.memory());
    for (int step = 0; step < 24; ++step) straight.step();
    for (int step = stop; step < 24; ++step) resumed.step();
    expect_same_flow(straight, resumed, 24);
  }
}

}  // namespace
}  // namespace dld::fluid
