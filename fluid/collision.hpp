// SPDX-License-Identifier: MIT
// What every collision operator shares: the two relaxation rates of a node, the state the fused
// kernel hands an operator (fluid/stream_collide.hpp), the moments with Guo's half-force shift, the
// second-order equilibrium, and the reference BGK/TRT collision `collide()` in plain loops, which
// the equivalence tests hold the operators' unrolled `relax()` to. The operators themselves are one
// file each in fluid/collision/ and one line in fluid/collision_registry.hpp.
// Guo, Zheng, Shi, PRE 65 046308 (2002), eq. (20): the source split into its symmetric and
// antisymmetric parts, each scaled by (1 - omega/2). All quantities in lattice units.
#pragma once
#include "fluid/d3q19.hpp"

namespace dld::fluid {

/// The two relaxation rates of a node: symmetric (omega+) and antisymmetric (omega-) part.
struct RelaxationRates {
  double plus, minus;
};

/// One node as the fused kernel hands it to an operator's `relax(f, s)`: the moments of its
/// streamed populations (u with the half-force shift), the force density on it and its rates.
struct NodeState {
  double rho, ux, uy, uz;
  double fx, fy, fz;
  double omega_plus, omega_minus;
};

/// Macroscopic moments with the half-force velocity shift of Guo forcing:
/// rho = sum f, rho u = sum f c + F/2.
struct Moments {
  double rho, ux, uy, uz;
};

/// c_I . u and c_I . F of a node, with direction I's components as compile-time constants.
struct Projections {
  double cu, cf;
};
template <int I>
[[gnu::always_inline]] inline Projections projections(const NodeState& s) {
  return {kC<I, 0> * s.ux + kC<I, 1> * s.uy + kC<I, 2> * s.uz,
          kC<I, 0> * s.fx + kC<I, 1> * s.fy + kC<I, 2> * s.fz};
}

template <typename Real>
inline Moments moments(const Real* f, double fx, double fy, double fz) {
  double rho = 0, jx = 0, jy = 0, jz = 0;
#pragma GCC unroll 19
  for (int i = 0; i < D3Q19::q; ++i) {
    rho += f[i];
    jx += f[i] * D3Q19::c[i][0];
    jy += f[i] * D3Q19::c[i][1];
    jz += f[i] * D3Q19::c[i][2];
  }
  double inv = 1.0 / rho;
  return {rho, (jx + 0.5 * fx) * inv, (jy + 0.5 * fy) * inv, (jz + 0.5 * fz) * inv};
}

/// Second-order equilibrium f_i^eq = w_i rho (1 + c.u/cs^2 + (c.u)^2/(2 cs^4) - u.u/(2 cs^2)).
inline double equilibrium(int i, double rho, double ux, double uy, double uz) {
  double cu = D3Q19::c[i][0] * ux + D3Q19::c[i][1] * uy + D3Q19::c[i][2] * uz;
  double uu = ux * ux + uy * uy + uz * uz;
  return D3Q19::w[i] * rho * (1.0 + 3.0 * cu + 4.5 * cu * cu - 1.5 * uu);
}

/// Reference collision: relaxes f (19 values) in place towards equilibrium with the Guo source for
/// force (fx, fy, fz); BGK is omega_plus == omega_minus, TRT (Ginzburg 2008) the pair split below.
/// Returns the moments used.
template <typename Real>
inline Moments collide(Real* f, double omega_plus, double omega_minus, double fx, double fy,
                       double fz) {
  const Moments m = moments(f, fx, fy, fz);
  const double uu = m.ux * m.ux + m.uy * m.uy + m.uz * m.uz;
  const double uf = m.ux * fx + m.uy * fy + m.uz * fz;
  const double kp = 1.0 - 0.5 * omega_plus;
  const double km = 1.0 - 0.5 * omega_minus;
  {  // rest population: purely symmetric
    const double w = D3Q19::w[0];
    const double feq = w * m.rho * (1.0 - 1.5 * uu);
    f[0] = f[0] - omega_plus * (f[0] - feq) + kp * w * (-3.0 * uf);
  }
#pragma GCC unroll 9
  for (int i = 1; i < D3Q19::q; i += 2) {
    const double w = D3Q19::w[i];
    const double cu = D3Q19::c[i][0] * m.ux + D3Q19::c[i][1] * m.uy + D3Q19::c[i][2] * m.uz;
    const double cf = D3Q19::c[i][0] * fx + D3Q19::c[i][1] * fy + D3Q19::c[i][2] * fz;
    const double feq_p = w * m.rho * (1.0 + 4.5 * cu * cu - 1.5 * uu);
    const double feq_m = w * m.rho * 3.0 * cu;
    const double s_p = w * (9.0 * cu * cf - 3.0 * uf);
    const double s_m = w * 3.0 * cf;
    const double fp = 0.5 * (f[i] + f[i + 1]);
    const double fm = 0.5 * (f[i] - f[i + 1]);
    const double dp = -omega_plus * (fp - feq_p) + kp * s_p;
    const double dm = -omega_minus * (fm - feq_m) + km * s_m;
    f[i] = static_cast<Real>(f[i] + dp + dm);
    f[i + 1] = static_cast<Real>(f[i + 1] + dp - dm);
  }
  return m;
}

}  // namespace dld::fluid
