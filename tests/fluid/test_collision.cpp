// SPDX-License-Identifier: MIT
// Properties every collision operator must have (lattice units).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

#include "fluid/collision_registry.hpp"
#include "mrt_reference.hpp"

namespace dld::fluid {
namespace {

struct Sums {
  double rho, jx, jy, jz;
};
Sums sums(const double* f) {
  Sums s{0, 0, 0, 0};
  for (int i = 0; i < D3Q19::q; ++i) {
    s.rho += f[i];
    s.jx += f[i] * D3Q19::c[i][0];
    s.jy += f[i] * D3Q19::c[i][1];
    s.jz += f[i] * D3Q19::c[i][2];
  }
  return s;
}

/// collide(f, F) must conserve mass, add exactly F to the momentum (Guo forcing) for random
/// populations, and leave an equilibrium alone when F = 0 (to 1e-16 or `ulps` units in the last
/// place, whichever is larger).
template <typename Collide>
void check_conservation(Collide&& collide, const std::string& what, double ulps = 1.0) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (int trial = 0; trial < 50; ++trial) {
    double f[D3Q19::q];
    for (int i = 0; i < D3Q19::q; ++i)
      f[i] = D3Q19::w[i] * (1.0 + noise(rng) * 10) + 0.001 * noise(rng);
    const double F[3] = {noise(rng) * 1e-3, noise(rng) * 1e-3, noise(rng) * 1e-3};
    const Sums before = sums(f);
    collide(f, F);
    const Sums after = sums(f);
    EXPECT_NEAR(after.rho, before.rho, 1e-15) << what;
    EXPECT_NEAR(after.jx, before.jx + F[0], 1e-16) << what;
    EXPECT_NEAR(after.jy, before.jy + F[1], 1e-16) << what;
    EXPECT_NEAR(after.jz, before.jz + F[2], 1e-16) << what;
  }
  const double rho = 1.03, u[3] = {0.02, -0.01, 0.005}, none[3] = {0, 0, 0};
  double f[D3Q19::q], g[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) f[i] = g[i] = equilibrium(i, rho, u[0], u[1], u[2]);
  collide(g, none);
  for (int i = 0; i < D3Q19::q; ++i)
    EXPECT_NEAR(g[i], f[i], std::max(1e-16, ulps * std::numeric_limits<double>::epsilon() * f[i]))
        << what << ", direction " << i;
}

/// The reference collide() with operator C's rates at tau.
template <typename C>
auto reference(double tau) {
  const RelaxationRates r = C::rates(tau, 3.0 / 16.0);
  return [r](double* f, const double* F) { collide(f, r.plus, r.minus, F[0], F[1], F[2]); };
}

TEST(Collision, ReferenceConservesAndKeepsTheEquilibrium) {
  check_conservation(reference<Bgk>(0.8), "reference BGK, tau 0.8");
  check_conservation(reference<Trt>(1.0), "reference TRT, tau 1");
  check_conservation(reference<Trt>(3.0), "reference TRT, tau 3");
}

TEST(Collision, TrtMagicParameterSetsOddRate) {
  const auto r = Trt::rates(1.0, 3.0 / 16.0);
  EXPECT_NEAR((1.0 / r.plus - 0.5) * (1.0 / r.minus - 0.5), 3.0 / 16.0, 1e-15);
}

/// One node through an operator's fast relax(), as the fused kernel calls it.
template <typename C>
void relax_node(double* f, const double* F, const RelaxationRates& r) {
  const Moments m = moments(f, F[0], F[1], F[2]);
  double g[D3Q19::q];
  std::copy(f, f + D3Q19::q, g);
  C::relax(g, NodeState{m.rho, m.ux, m.uy, m.uz, F[0], F[1], F[2], r.plus, r.minus},
           [&]<int I>(std::integral_constant<int, I>, double value) { f[I] = value; });
}

template <typename C>
void check_operator_properties(double tau) {
  const RelaxationRates r = C::rates(tau, 3.0 / 16.0);
  // A few units in the last place at equilibrium: MRT sums 19 moments forth and back.
  check_conservation([&](double* f, const double* F) { relax_node<C>(f, F, r); },
                     std::string(C::kName) + ", tau " + std::to_string(tau), 4.0);
}

// Every registered operator conserves mass, adds F to the momentum, and leaves the equilibrium
// alone, at the tau outside (1) and inside (3) the cells.
TEST(Collision, EveryOperatorConservesAndKeepsItsEquilibrium) {
  [&]<std::size_t... K>(std::index_sequence<K...>) {
    (check_operator_properties<std::tuple_element_t<K, CollisionOperators>>(1.0), ...);
    (check_operator_properties<std::tuple_element_t<K, CollisionOperators>>(3.0), ...);
  }
  (std::make_index_sequence<std::tuple_size_v<CollisionOperators>>{});
}

// The matrix MRT with every even rate at omega+ (and the odd at omega-) is TRT: this checks the
// reference's basis, inverse and forcing against an independent formula; with d'Humieres' rates
// it is not TRT.
TEST(Collision, MrtWithEvenRatesEqualIsTrt) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  const RelaxationRates r = Trt::rates(1.7, 3.0 / 16.0);
  double worst_equal = 0, worst_dhumieres = 0;
  for (int trial = 0; trial < 20; ++trial) {
    double f[D3Q19::q], trt[D3Q19::q], mrt[D3Q19::q], dh[D3Q19::q];
    for (int i = 0; i < D3Q19::q; ++i) f[i] = D3Q19::w[i] * (1.0 + noise(rng) * 10);
    const double F[3] = {noise(rng) * 1e-3, noise(rng) * 1e-3, noise(rng) * 1e-3};
    std::copy(f, f + D3Q19::q, trt);
    std::copy(f, f + D3Q19::q, mrt);
    std::copy(f, f + D3Q19::q, dh);
    collide(trt, r.plus, r.minus, F[0], F[1], F[2]);
    testing::mrt_reference_collide(mrt, testing::mrt_rates(r.plus, r.minus, r.plus), F[0], F[1],
                                   F[2]);
    testing::mrt_reference_collide(dh, testing::mrt_rates(r.plus, r.minus), F[0], F[1], F[2]);
    for (int i = 0; i < D3Q19::q; ++i) {
      worst_equal = std::max(worst_equal, std::abs(mrt[i] - trt[i]));
      worst_dhumieres = std::max(worst_dhumieres, std::abs(dh[i] - trt[i]));
    }
  }
  EXPECT_LT(worst_equal, 1e-15);
  EXPECT_GT(worst_dhumieres, 1e-6);
}

TEST(Collision, MomentsIncludeHalfForce) {
  double f[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) f[i] = equilibrium(i, 1.0, 0.01, 0.0, 0.0);
  const Moments m = moments(f, 2e-3, 0.0, 0.0);
  EXPECT_NEAR(m.ux, 0.01 + 1e-3, 1e-15);
}

}  // namespace
}  // namespace dld::fluid
