// SPDX-License-Identifier: MIT
// Multiple-relaxation-time collision (d'Humieres, Ginzburg, Krafczyk, Lallemand, Luo, Phil. Trans.
// R. Soc. Lond. A 360 (2002) 437): the populations are mapped to 19 orthogonal moments (their
// Appendix A basis), each relaxed at its own rate, and mapped back with M^-1 = M^T diag(1/|M_a|^2).
// Rates: the five shear stresses relax with omega+ = 1/tau (the viscosity); the odd non-conserved
// moments (energy flux q, third-order m) with TRT's omega- from the magic parameter, so the walls
// sit where TRT puts them (Lambda = 3/16: exact for Poiseuille); energy, energy square and the
// stress ghosts pi with d'Humieres' 1.19, 1.4 and 1.4 (bulk viscosity (2/9)(1/1.19 - 1/2)). With
// every even rate equal to omega+ this is TRT (a test checks that). Guo forcing in moment space: m*
// = m - S (m - m_eq) + (I - S/2) M G, m_eq = M f_eq; as f* = f + G + M^-1 S M (f_eq - f - G/2). Why
// MRT and not regularised BGK: it keeps TRT's wall placement, adds separate bulk and ghost rates
// (the damping that lets high tau inside cells and low tau outside coexist), and contains TRT as a
// special case the tests can check. Lattice units.
#pragma once
#include <array>
#include <type_traits>
#include <utility>

#include "fluid/collision.hpp"
#include "fluid/collision/trt.hpp"

namespace dld::fluid {

namespace mrt {

/// Row a of d'Humieres' moment matrix at velocity c (Phil. Trans. 2002, Appendix A).
constexpr double basis(int a, const std::array<int, 3>& c) {
  const int x = c[0], y = c[1], z = c[2];
  const int c2 = x * x + y * y + z * z;
  switch (a) {
    case 0:
      return 1;  // rho
    case 1:
      return 19 * c2 - 30;  // e
    case 2:
      return (21 * c2 * c2 - 53 * c2 + 24) / 2.0;  // epsilon
    case 3:
      return x;  // j_x
    case 4:
      return (5 * c2 - 9) * x;  // q_x
    case 5:
      return y;  // j_y
    case 6:
      return (5 * c2 - 9) * y;  // q_y
    case 7:
      return z;  // j_z
    case 8:
      return (5 * c2 - 9) * z;  // q_z
    case 9:
      return 3 * x * x - c2;  // 3 p_xx
    case 10:
      return (3 * c2 - 5) * (3 * x * x - c2);  // 3 pi_xx
    case 11:
      return y * y - z * z;  // p_ww
    case 12:
      return (3 * c2 - 5) * (y * y - z * z);  // pi_ww
    case 13:
      return x * y;  // p_xy
    case 14:
      return y * z;  // p_yz
    case 15:
      return x * z;  // p_xz
    case 16:
      return (y * y - z * z) * x;  // m_x
    case 17:
      return (z * z - x * x) * y;  // m_y
    default:
      return (x * x - y * y) * z;  // m_z
  }
}

inline constexpr auto kM = [] {
  std::array<std::array<double, D3Q19::q>, D3Q19::q> m{};
  for (int a = 0; a < D3Q19::q; ++a)
    for (int i = 0; i < D3Q19::q; ++i) m[a][i] = basis(a, D3Q19::c[i]);
  return m;
}();

/// 1 / |M_a|^2: the rows are orthogonal, so M^-1 = M^T diag(1 / |M_a|^2).
inline constexpr auto kInverseNorm2 = [] {
  std::array<double, D3Q19::q> n{};
  for (int a = 0; a < D3Q19::q; ++a) {
    double s = 0;
    for (int i = 0; i < D3Q19::q; ++i) s += kM[a][i] * kM[a][i];
    n[a] = 1.0 / s;
  }
  return n;
}();

/// What relaxes moment a: conserved (rho, j), the viscosity's omega+, TRT's omega-, or a constant.
enum class Rate { kConserved, kPlus, kMinus, kEnergy, kEnergySquare, kGhostStress };
inline constexpr std::array<Rate, D3Q19::q> kRateOf{
    Rate::kConserved,   Rate::kEnergy, Rate::kEnergySquare, Rate::kConserved, Rate::kMinus,
    Rate::kConserved,   Rate::kMinus,  Rate::kConserved,    Rate::kMinus,     Rate::kPlus,
    Rate::kGhostStress, Rate::kPlus,   Rate::kGhostStress,  Rate::kPlus,      Rate::kPlus,
    Rate::kPlus,        Rate::kMinus,  Rate::kMinus,        Rate::kMinus};
inline constexpr double kEnergyRate = 1.19;       ///< s_1 of d'Humieres et al. 2002
inline constexpr double kEnergySquareRate = 1.4;  ///< s_2
inline constexpr double kGhostStressRate = 1.4;   ///< s_10 = s_12

constexpr bool orthogonal() {
  for (int a = 0; a < D3Q19::q; ++a)
    for (int b = a + 1; b < D3Q19::q; ++b) {
      double s = 0;
      for (int i = 0; i < D3Q19::q; ++i) s += kM[a][i] * kM[b][i];
      if (s != 0.0) return false;
    }
  return true;
}
static_assert(orthogonal(), "d'Humieres' D3Q19 moment basis must be orthogonal");

/// Row a is even in c (rho, e, eps, the stresses, pi) or odd (j, q, m); opposite directions
/// (2k-1, 2k) then carry equal or opposite entries, so a row needs only the pairs' sums or
/// differences: half the products.
inline constexpr auto kEven = [] {
  std::array<bool, D3Q19::q> even{};
  for (int a = 0; a < D3Q19::q; ++a) {
    even[a] = true;
    for (int i = 1; i < D3Q19::q; i += 2) even[a] = even[a] && kM[a][i] == kM[a][i + 1];
  }
  return even;
}();
constexpr bool rows_have_parity() {
  for (int a = 0; a < D3Q19::q; ++a)
    for (int i = 1; i < D3Q19::q; i += 2)
      if (kM[a][i] != (kEven[a] ? kM[a][i + 1] : -kM[a][i + 1])) return false;
  return true;
}
static_assert(rows_have_parity(), "every moment must be even or odd in c");

/// Pair P of the populations: P = 0 the rest population, P = k the directions (2k-1, 2k).
inline constexpr int kPairs = (D3Q19::q + 1) / 2;

template <int A, int P>
inline void add_term(double& acc, const double (&even)[kPairs], const double (&odd)[kPairs]) {
  constexpr int i = P == 0 ? 0 : 2 * P - 1;
  if constexpr (kM[A][i] != 0.0) acc += kM[A][i] * (kEven[A] ? even[P] : odd[P]);
}

/// (M d)_A from the pairs' sums (`even`) or differences (`odd`), zero entries left out.
template <int A, int... P>
inline double project(const double (&even)[kPairs], const double (&odd)[kPairs],
                      std::integer_sequence<int, P...>) {
  double acc = 0.0;
  (add_term<A, P>(acc, even, odd), ...);
  return acc;
}

}  // namespace mrt

struct Mrt {
  static constexpr const char* kName = "mrt";
  /// omega+ and omega- as TRT's (the relaxation field stores these two per node).
  static RelaxationRates rates(double tau, double magic) { return Trt::rates(tau, magic); }

  /// Post-collision populations of one node, handed to store(std::integral_constant<int, I>,
  /// value) direction by direction.
  template <typename Store>
  [[gnu::always_inline, gnu::flatten]] static void relax(const double (&f)[D3Q19::q],
                                                         const NodeState& s, Store&& store) {
    using Rows = std::make_integer_sequence<int, D3Q19::q>;
    using Pairs = std::make_integer_sequence<int, mrt::kPairs>;
    const double uu = s.ux * s.ux + s.uy * s.uy + s.uz * s.uz;
    const double uf = s.ux * s.fx + s.uy * s.fy + s.uz * s.fz;
    // Per pair: the Guo source and d = f_eq - f - G/2, split into even and odd parts.
    double source_even[mrt::kPairs], source_odd[mrt::kPairs], d_even[mrt::kPairs],
        d_odd[mrt::kPairs];
    source_even[0] = D3Q19::w[0] * (-3.0 * uf);
    source_odd[0] = 0.0;
    d_even[0] = D3Q19::w[0] * s.rho * (1.0 - 1.5 * uu) - f[0] - 0.5 * source_even[0];
    d_odd[0] = 0.0;
    [&]<int... K>(std::integer_sequence<int, K...>) {
      auto pair = [&]<int P>(std::integer_sequence<int, P>) {
        constexpr int I = 2 * P - 1;
        constexpr double w = D3Q19::w[I];
        const auto [cu, cf] = projections<I>(s);
        source_even[P] = w * (9.0 * cu * cf - 3.0 * uf);
        source_odd[P] = w * 3.0 * cf;
        const double eq_even = w * s.rho * (1.0 + 4.5 * cu * cu - 1.5 * uu);
        const double eq_odd = w * s.rho * 3.0 * cu;
        // Sums and differences over the pair (f_eq - f - G/2 at I plus / minus at I + 1).
        d_even[P] = 2.0 * eq_even - (f[I] + f[I + 1]) - source_even[P];
        d_odd[P] = 2.0 * eq_odd - (f[I] - f[I + 1]) - source_odd[P];
      };
      (pair(std::integer_sequence<int, K + 1>{}), ...);
    }
    (std::make_integer_sequence<int, mrt::kPairs - 1>{});
    // S M d / |M_a|^2 for the relaxing moments (those of rho and j vanish: f_eq and G/2 carry
    // them).
    double md[D3Q19::q];
    [&]<int... A>(std::integer_sequence<int, A...>) {
      auto one = [&]<int B>(std::integer_sequence<int, B>) {
        constexpr mrt::Rate r = mrt::kRateOf[B];
        if constexpr (r == mrt::Rate::kConserved) {
          md[B] = 0.0;
        } else {
          const double rate = r == mrt::Rate::kPlus           ? s.omega_plus
                              : r == mrt::Rate::kMinus        ? s.omega_minus
                              : r == mrt::Rate::kEnergy       ? mrt::kEnergyRate
                              : r == mrt::Rate::kEnergySquare ? mrt::kEnergySquareRate
                                                              : mrt::kGhostStressRate;
          md[B] = rate * mrt::kInverseNorm2[B] * mrt::project<B>(d_even, d_odd, Pairs{});
        }
      };
      (one(std::integer_sequence<int, A>{}), ...);
    }
    (Rows{});
    // f* = f + G + M^T md, the even rows' share equal and the odd rows' opposite within a pair.
    [&]<int... K>(std::integer_sequence<int, K...>) {
      auto pair = [&]<int P>(std::integer_sequence<int, P>) {
        constexpr int I = P == 0 ? 0 : 2 * P - 1;
        double even = 0.0, odd = 0.0;
        [&]<int... A>(std::integer_sequence<int, A...>) {
          auto term = [&]<int B>(std::integer_sequence<int, B>) {
            if constexpr (mrt::kRateOf[B] != mrt::Rate::kConserved && mrt::kM[B][I] != 0.0) {
              if constexpr (mrt::kEven[B])
                even += mrt::kM[B][I] * md[B];
              else
                odd += mrt::kM[B][I] * md[B];
            }
          };
          (term(std::integer_sequence<int, A>{}), ...);
        }
        (Rows{});
        if constexpr (P == 0) {
          store(std::integral_constant<int, 0>{}, f[0] + source_even[0] + even);
        } else {
          store(std::integral_constant<int, I>{},
                f[I] + (source_even[P] + source_odd[P]) + (even + odd));
          store(std::integral_constant<int, I + 1>{},
                f[I + 1] + (source_even[P] - source_odd[P]) + (even - odd));
        }
      };
      (pair(std::integer_sequence<int, K>{}), ...);
    }
    (Pairs{});
  }
};

}  // namespace dld::fluid
