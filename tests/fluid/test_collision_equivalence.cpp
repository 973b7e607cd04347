// SPDX-License-Identifier: MIT
// Sweep equivalence (after waLBerla's): the fused stream-collide kernel, for every operator of
// fluid/collision_registry.hpp, against a reference written the slow way: pull each population
// from the neighbour's coordinates, collide with the operator's reference formula (plain loops:
// collide() for BGK and TRT, the matrix MRT of mrt_reference.hpp), node by node. On a DLD box
// with a fractional row shift (the shifted x face interpolates), the pillar and the z walls, with
// and without the force and relaxation-time fields. Lattice units.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "dld_scene.hpp"
#include "fluid/bounce_back.hpp"
#include "fluid/collision_registry.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/periodic_ghosts.hpp"
#include "fluid/stream_collide.hpp"
#include "mrt_reference.hpp"

namespace dld::fluid {
namespace {

/// The reference collision of each operator; a new operator without one does not compile here.
template <typename C>
void reference_collide(double* f, const RelaxationRates& r, const double* F);
template <>
void reference_collide<Bgk>(double* f, const RelaxationRates& r, const double* F) {
  collide(f, r.plus, r.plus, F[0], F[1], F[2]);
}
template <>
void reference_collide<Trt>(double* f, const RelaxationRates& r, const double* F) {
  collide(f, r.plus, r.minus, F[0], F[1], F[2]);
}
template <>
void reference_collide<Mrt>(double* f, const RelaxationRates& r, const double* F) {
  testing::mrt_reference_collide(f, testing::mrt_rates(r.plus, r.minus), F[0], F[1], F[2]);
}

struct Fields {
  std::vector<double> force, plus, minus, velocity;
};

/// Random populations, force and relaxation times on every padded node; ghosts and bounce-back
/// slots filled as a step does before streaming.
template <typename C>
std::vector<double> prepared_populations(const Lattice& L, Fields& fields, std::mt19937& rng) {
  const std::size_t n = L.padded_size();
  std::uniform_real_distribution<double> unit(-1.0, 1.0), tau(0.55, 3.0);
  std::vector<double> f(n * D3Q19::q + kPopulationPadding, 0.0);
  for (int q = 0; q < D3Q19::q; ++q)
    for (std::size_t s = 0; s < n; ++s) f[q * n + s] = D3Q19::w[q] * (1.0 + 0.05 * unit(rng));
  fields.force.resize(3 * n);
  for (double& v : fields.force) v = 1e-3 * unit(rng);
  fields.plus.resize(n);
  fields.minus.resize(n);
  for (std::size_t s = 0; s < n; ++s) {
    const RelaxationRates r = C::rates(tau(rng), 3.0 / 16.0);
    fields.plus[s] = r.plus, fields.minus[s] = r.minus;
  }
  fields.velocity.assign(3 * n, 0.0);
  fill_periodic_ghosts(L, f.data());
  apply_bounce_back(L, f.data());
  return f;
}

struct Differences {
  double populations = 0, velocity = 0;
  std::size_t nodes = 0;
};

/// Largest differences between the fused kernel of operator C and the reference of operator R.
template <typename C, typename R = C>
Differences compare(bool force_field, bool tau_field) {
  const Lattice L(fluid_config(testing::dld_scene(1.6, 1.5)).domain);
  EXPECT_NE(L.domain().shift, std::floor(L.domain().shift)) << "the x face must interpolate";
  const std::size_t n = L.padded_size();
  std::mt19937 rng(11);
  Fields fl;
  const std::vector<double> src = prepared_populations<C>(L, fl, rng);
  std::vector<double> dst(src.size(), 0.0);
  KernelParams p;
  p.tau = 0.8;
  p.force[0] = 2e-5, p.force[1] = -1e-5;
  for (int a = 0; a < 3 && force_field; ++a) {
    p.force_field[a] = fl.force.data() + a * n;
    p.velocity[a] = fl.velocity.data() + a * n;
  }
  if (tau_field) p.rate_plus = fl.plus.data(), p.rate_minus = fl.minus.data();
  if (force_field && tau_field) stream_collide<C, true, true>(L, src.data(), dst.data(), p);
  if (force_field && !tau_field) stream_collide<C, true, false>(L, src.data(), dst.data(), p);
  if (!force_field && tau_field) stream_collide<C, false, true>(L, src.data(), dst.data(), p);
  if (!force_field && !tau_field) stream_collide<C, false, false>(L, src.data(), dst.data(), p);

  const RelaxationRates uniform = C::rates(p.tau, p.magic);
  Differences d;
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        if (L.solid(i, j, k)) continue;
        const std::size_t s = L.index(i, j, k);
        double f[D3Q19::q];
        for (int q = 0; q < D3Q19::q; ++q)
          f[q] = src[q * n + L.index(i - D3Q19::c[q][0], j - D3Q19::c[q][1], k - D3Q19::c[q][2])];
        double F[3] = {p.force[0], p.force[1], p.force[2]};
        for (int a = 0; a < 3 && force_field; ++a) F[a] += fl.force[a * n + s];
        const RelaxationRates r = tau_field ? RelaxationRates{fl.plus[s], fl.minus[s]} : uniform;
        const Moments m = moments(f, F[0], F[1], F[2]);
        reference_collide<R>(f, r, F);
        for (int q = 0; q < D3Q19::q; ++q)
          d.populations = std::max(d.populations, std::abs(dst[q * n + s] - f[q]));
        if (force_field) {
          const double u[3] = {m.ux, m.uy, m.uz};
          for (int a = 0; a < 3; ++a)
            d.velocity = std::max(d.velocity, std::abs(fl.velocity[a * n + s] - u[a]));
        }
        ++d.nodes;
      }
  return d;
}

template <typename C>
void check_all_variants() {
  for (bool ff : {false, true})
    for (bool tf : {false, true}) {
      const Differences d = compare<C>(ff, tf);
      const Lattice L(fluid_config(testing::dld_scene(1.6, 1.5)).domain);
      std::printf(
          "%s, force field %d, relaxation field %d: %zu nodes, largest difference %.2e"
          " (populations), %.2e (velocity)\n",
          C::kName, ff, tf, d.nodes, d.populations, d.velocity);
      EXPECT_EQ(d.nodes, L.fluid_nodes());
      EXPECT_LT(d.populations, 1e-13)
          << C::kName << ", force field " << ff << ", relaxation field " << tf;
      EXPECT_LT(d.velocity, 1e-15) << C::kName << ", force field " << ff;
    }
}

TEST(CollisionEquivalence, FusedKernelMatchesReferenceForEveryOperator) {
  [&]<std::size_t... K>(std::index_sequence<K...>) {
    (check_all_variants<std::tuple_element_t<K, CollisionOperators>>(), ...);
  }
  (std::make_index_sequence<std::tuple_size_v<CollisionOperators>>{});
}

// The comparison bites: one operator's kernel against another's reference differs by far more
// than the tolerance, and so do TRT and MRT (which share omega+ and omega-).
TEST(CollisionEquivalence, ComparisonTellsOperatorsApart) {
  EXPECT_GT((compare<Trt, Bgk>(true, true).populations), 1e-7);
  EXPECT_GT((compare<Mrt, Trt>(true, true).populations), 1e-7);
  EXPECT_GT((compare<Trt, Mrt>(false, false).populations), 1e-7);
}

}  // namespace
}  // namespace dld::fluid
