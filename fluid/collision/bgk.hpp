// SPDX-License-Identifier: MIT
// Single-relaxation-time (BGK) collision with Guo forcing: every population relaxes towards the
// second-order equilibrium with omega = 1/tau (Qian, d'Humieres, Lallemand, EPL 17 (1992) 479),
// source w_i (1 - omega/2) [3 (c_i - u) + 9 (c_i . u) c_i] . F (Guo et al. 2002). Lattice units.
#pragma once
#include <type_traits>
#include <utility>

#include "fluid/collision.hpp"

namespace dld::fluid {

struct Bgk {
  static constexpr const char* kName = "bgk";
  /// Both parts relax with 1/tau (the Rates layout of TRT, so one relaxation field serves both).
  static RelaxationRates rates(double tau, double /*magic*/) { return {1.0 / tau, 1.0 / tau}; }

  /// Post-collision populations of one node, handed to store(std::integral_constant<int, I>,
  /// value); directions unrolled at compile time and taken in opposite pairs (c_-i = -c_i) so each
  /// pair computes c.u and c.F once.
  template <typename Store>
  [[gnu::always_inline, gnu::flatten]] static void relax(const double (&f)[D3Q19::q],
                                                         const NodeState& s, Store&& store) {
    const double omega = s.omega_plus, k = 1.0 - 0.5 * omega;
    const double uu = s.ux * s.ux + s.uy * s.uy + s.uz * s.uz;
    const double uf = s.ux * s.fx + s.uy * s.fy + s.uz * s.fz;
    store(std::integral_constant<int, 0>{},
          f[0] - omega * (f[0] - D3Q19::w[0] * s.rho * (1.0 - 1.5 * uu)) +
              k * D3Q19::w[0] * (-3.0 * uf));
    auto pair = [&]<int I>(std::integer_sequence<int, I>) {
      constexpr double w = D3Q19::w[I];
      const auto [cu, cf] = projections<I>(s);
      const double even = w * s.rho * (1.0 + 4.5 * cu * cu - 1.5 * uu), odd = w * s.rho * 3.0 * cu;
      const double source_even = k * w * (9.0 * cu * cf - 3.0 * uf), source_odd = k * w * 3.0 * cf;
      store(std::integral_constant<int, I>{},
            f[I] - omega * (f[I] - (even + odd)) + (source_even + source_odd));
      store(std::integral_constant<int, I + 1>{},
            f[I + 1] - omega * (f[I + 1] - (even - odd)) + (source_even - source_odd));
    };
    [&]<int... K>(std::integer_sequence<int, K...>) {
      (pair(std::integer_sequence<int, 2 * K + 1>{}), ...);
    }
    (std::make_integer_sequence<int, (D3Q19::q - 1) / 2>{});
  }
};

}  // namespace dld::fluid
