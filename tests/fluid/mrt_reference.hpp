// SPDX-License-Identifier: MIT
// The MRT collision written the textbook way, for the tests to hold fluid/collision/mrt.hpp to:
// m = M f, m* = m - S (m - M f_eq) + (I - S/2) M G, f* = M^-1 m* with M^-1 from Gauss-Jordan
// elimination (not from the rows' orthogonality, as the fast path takes it) and every moment's
// rate spelled out (d'Humieres et al., Phil. Trans. R. Soc. Lond. A 360 (2002) 437, Appendix A;
// the rates of fluid/collision/mrt.hpp). Lattice units.
#pragma once
#include <array>
#include <cmath>
#include <stdexcept>

#include "fluid/collision.hpp"

namespace dld::fluid::testing {

using Matrix19 = std::array<std::array<double, D3Q19::q>, D3Q19::q>;

/// d'Humieres' 19 moments of one velocity, in their order (rho, e, eps, j_x, q_x, ..., m_z).
inline std::array<double, D3Q19::q> moment_row_values(double x, double y, double z) {
  const double c2 = x * x + y * y + z * z;
  return {1.0,
          19 * c2 - 30,
          (21 * c2 * c2 - 53 * c2 + 24) / 2,
          x,
          (5 * c2 - 9) * x,
          y,
          (5 * c2 - 9) * y,
          z,
          (5 * c2 - 9) * z,
          3 * x * x - c2,
          (3 * c2 - 5) * (3 * x * x - c2),
          y * y - z * z,
          (3 * c2 - 5) * (y * y - z * z),
          x * y,
          y * z,
          x * z,
          (y * y - z * z) * x,
          (z * z - x * x) * y,
          (x * x - y * y) * z};
}

inline Matrix19 moment_matrix() {
  Matrix19 m{};
  for (int i = 0; i < D3Q19::q; ++i) {
    const auto col = moment_row_values(D3Q19::c[i][0], D3Q19::c[i][1], D3Q19::c[i][2]);
    for (int a = 0; a < D3Q19::q; ++a) m[a][i] = col[a];
  }
  return m;
}

/// Inverse by Gauss-Jordan elimination with partial pivoting.
inline Matrix19 inverse(Matrix19 a) {
  Matrix19 inv{};
  for (int i = 0; i < D3Q19::q; ++i) inv[i][i] = 1.0;
  for (int col = 0; col < D3Q19::q; ++col) {
    int pivot = col;
    for (int r = col + 1; r < D3Q19::q; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    if (a[pivot][col] == 0.0) throw std::runtime_error("moment matrix is singular");
    std::swap(a[col], a[pivot]);
    std::swap(inv[col], inv[pivot]);
    const double p = a[col][col];
    for (int k = 0; k < D3Q19::q; ++k) a[col][k] /= p, inv[col][k] /= p;
    for (int r = 0; r < D3Q19::q; ++r) {
      if (r == col || a[r][col] == 0.0) continue;
      const double factor = a[r][col];
      for (int k = 0; k < D3Q19::q; ++k)
        a[r][k] -= factor * a[col][k], inv[r][k] -= factor * inv[col][k];
    }
  }
  return inv;
}

/// The 19 rates: rho and j 0 (conserved), the five stresses omega+, q and m omega-, e / eps / pi
/// d'Humieres' 1.19 / 1.4 / 1.4 unless `even` overrides every non-conserved even moment's rate.
inline std::array<double, D3Q19::q> mrt_rates(double plus, double minus, double even = -1.0) {
  const double e = even > 0 ? even : 1.19, eps = even > 0 ? even : 1.4, pi = even > 0 ? even : 1.4;
  return {0,  e,    eps, 0,    minus, 0,    minus, 0,     minus, plus,
          pi, plus, pi,  plus, plus,  plus, minus, minus, minus};
}

/// One node's MRT collision with Guo forcing, in place.
inline void mrt_reference_collide(double* f, const std::array<double, D3Q19::q>& s, double fx,
                                  double fy, double fz) {
  static const Matrix19 M = moment_matrix();
  static const Matrix19 Minv = inverse(M);
  const Moments mo = moments(f, fx, fy, fz);
  double feq[D3Q19::q], G[D3Q19::q];
  for (int i = 0; i < D3Q19::q; ++i) {
    feq[i] = equilibrium(i, mo.rho, mo.ux, mo.uy, mo.uz);
    const double c[3] = {double(D3Q19::c[i][0]), double(D3Q19::c[i][1]), double(D3Q19::c[i][2])};
    const double cu = c[0] * mo.ux + c[1] * mo.uy + c[2] * mo.uz;
    const double F[3] = {fx, fy, fz};
    const double u[3] = {mo.ux, mo.uy, mo.uz};
    G[i] = 0;
    for (int a = 0; a < 3; ++a)
      G[i] += D3Q19::w[i] * (3.0 * (c[a] - u[a]) + 9.0 * cu * c[a]) * F[a];
  }
  double post[D3Q19::q];
  for (int a = 0; a < D3Q19::q; ++a) {
    double m = 0, meq = 0, g = 0;
    for (int i = 0; i < D3Q19::q; ++i)
      m += M[a][i] * f[i], meq += M[a][i] * feq[i], g += M[a][i] * G[i];
    post[a] = m - s[a] * (m - meq) + (1.0 - 0.5 * s[a]) * g;
  }
  for (int i = 0; i < D3Q19::q; ++i) {
    double v = 0;
    for (int a = 0; a < D3Q19::q; ++a) v += Minv[i][a] * post[a];
    f[i] = v;
  }
}

}  // namespace dld::fluid::testing
