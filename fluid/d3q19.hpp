// SPDX-License-Identifier: MIT
// D3Q19 stencil geometry: velocities, weights, opposites. Weights are checked against the
// isotropy conditions at compile time, so they cannot drift from the velocity table.
#pragma once
#include <array>

namespace dld::fluid {

struct D3Q19 {
  static constexpr int q = 19;
  static constexpr double cs2 = 1.0 / 3.0;  ///< lattice speed of sound squared
  // Rest, 6 axis neighbours, 12 edge neighbours; opposite pairs are adjacent (i, i+1) for i >= 1.
  static constexpr std::array<std::array<int, 3>, q> c{{
      {0, 0, 0},  {1, 0, 0},   {-1, 0, 0},  {0, 1, 0},  {0, -1, 0}, {0, 0, 1},   {0, 0, -1},
      {1, 1, 0},  {-1, -1, 0}, {1, -1, 0},  {-1, 1, 0}, {1, 0, 1},  {-1, 0, -1}, {1, 0, -1},
      {-1, 0, 1}, {0, 1, 1},   {0, -1, -1}, {0, 1, -1}, {0, -1, 1},
  }};
  // Weight by speed |c|^2 = 0, 1, 2: 1/3, 1/18, 1/36.
  static constexpr std::array<double, q> w = [] {
    std::array<double, q> out{};
    for (int i = 0; i < q; ++i) {
      int n = c[i][0] * c[i][0] + c[i][1] * c[i][1] + c[i][2] * c[i][2];
      out[i] = n == 0 ? 1.0 / 3.0 : (n == 1 ? 1.0 / 18.0 : 1.0 / 36.0);
    }
    return out;
  }();
  static constexpr std::array<int, q> opp = [] {
    std::array<int, q> out{};
    for (int i = 0; i < q; ++i)
      for (int j = 0; j < q; ++j)
        if (c[j][0] == -c[i][0] && c[j][1] == -c[i][1] && c[j][2] == -c[i][2]) out[i] = j;
    return out;
  }();
};

/// Component A of velocity I as a compile-time constant: unrolled kernels fold it into their
/// arithmetic (0 and 1 cost nothing).
template <int I, int A>
inline constexpr double kC = static_cast<double>(D3Q19::c[I][A]);

namespace detail {
constexpr bool weights_isotropic() {
  double s0 = 0, s2[3][3] = {};
  double s1[3] = {};
  for (int i = 0; i < D3Q19::q; ++i) {
    s0 += D3Q19::w[i];
    for (int a = 0; a < 3; ++a) {
      s1[a] += D3Q19::w[i] * D3Q19::c[i][a];
      for (int b = 0; b < 3; ++b) s2[a][b] += D3Q19::w[i] * D3Q19::c[i][a] * D3Q19::c[i][b];
    }
  }
  auto near = [](double x, double y) { return x - y < 1e-15 && y - x < 1e-15; };
  bool ok = near(s0, 1.0);
  for (int a = 0; a < 3; ++a) {
    ok = ok && near(s1[a], 0.0);
    for (int b = 0; b < 3; ++b) ok = ok && near(s2[a][b], a == b ? D3Q19::cs2 : 0.0);
  }
  for (int i = 1; i < D3Q19::q; i += 2) ok = ok && D3Q19::opp[i] == i + 1;
  return ok && D3Q19::opp[0] == 0;
}
static_assert(weights_isotropic(), "D3Q19 weights must sum to 1 with second moment cs^2 I");
}  // namespace detail

}  // namespace dld::fluid
