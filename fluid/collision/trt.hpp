// SPDX-License-Identifier: MIT
// Two-relaxation-time collision (Ginzburg, Verhaeghe, d'Humieres, Commun. Comput. Phys. 3 (2008)
// 427): the symmetric part of each pair (f_i, f_-i) relaxes with omega+ (the viscosity,
// nu = (1/omega+ - 1/2)/3), the antisymmetric part with omega-, set by the magic parameter
// Lambda = (1/omega+ - 1/2)(1/omega- - 1/2); Lambda = 3/16 puts half-way bounce-back walls exactly
// in place for Poiseuille flow. Guo forcing split the same way (fluid/collision.hpp). Lattice
// units.
#pragma once
#include <type_traits>
#include <utility>

#include "fluid/collision.hpp"

namespace dld::fluid {

struct Trt {
  static constexpr const char* kName = "trt";
  static RelaxationRates rates(double tau, double magic) {
    return {1.0 / tau, 1.0 / (0.5 + magic / (tau - 0.5))};
  }

  /// Post-collision populations of one node, handed to store(std::integral_constant<int, I>,
  /// value) direction by direction; directions unrolled at compile time.
  template <typename Store>
  [[gnu::always_inline, gnu::flatten]] static void relax(const double (&f)[D3Q19::q],
                                                         const NodeState& s, Store&& store) {
    const double op = s.omega_plus, om = s.omega_minus;
    const double uu = s.ux * s.ux + s.uy * s.uy + s.uz * s.uz;
    const double uf = s.ux * s.fx + s.uy * s.fy + s.uz * s.fz;
    const double kp = 1.0 - 0.5 * op, km = 1.0 - 0.5 * om;
    store(std::integral_constant<int, 0>{},
          f[0] - op * (f[0] - D3Q19::w[0] * s.rho * (1.0 - 1.5 * uu)) +
              kp * D3Q19::w[0] * (-3.0 * uf));
    auto pair = [&]<int I>(std::integer_sequence<int, I>) {
      constexpr double w = D3Q19::w[I];
      const auto [cu, cf] = projections<I>(s);
      const double feq_p = w * s.rho * (1.0 + 4.5 * cu * cu - 1.5 * uu);
      const double feq_m = w * s.rho * 3.0 * cu;
      const double fp = 0.5 * (f[I] + f[I + 1]);
      const double fm = 0.5 * (f[I] - f[I + 1]);
      const double dp = -op * (fp - feq_p) + kp * w * (9.0 * cu * cf - 3.0 * uf);
      const double dm = -om * (fm - feq_m) + km * w * 3.0 * cf;
      store(std::integral_constant<int, I>{}, f[I] + dp + dm);
      store(std::integral_constant<int, I + 1>{}, f[I + 1] + dp - dm);
    };
    [&]<int... K>(std::integer_sequence<int, K...>) {
      (pair(std::integer_sequence<int, 2 * K + 1>{}), ...);
    }
    (std::make_integer_sequence<int, (D3Q19::q - 1) / 2>{});
  }
};

}  // namespace dld::fluid
