// SPDX-License-Identifier: MIT
#include "fluid/observables.hpp"

#include <cassert>
#include <cmath>

namespace dld::fluid {

GapProfile gap_profile(const FluidSolver& solver, const DldCell& cell) {
  const Lattice& L = solver.lattice();
  const int nx = L.nx(), ny = L.ny(), nz = L.nz();
  // u_x on the plane x = xp, linearly between the two node columns around it.
  const double xp = cell.pillar_x();
  const int i0 = static_cast<int>(std::floor(xp - 0.5));
  const double a = (xp - 0.5) - i0;
  const double y_low = cell.pillar_y() + cell.radius;
  const double y_high = cell.pillar_y() + cell.lambda - cell.radius;

  GapProfile p;
  p.width = y_high - y_low;
  for (int j = static_cast<int>(std::floor(y_low)); j <= static_cast<int>(std::ceil(y_high)); ++j) {
    const double yc = j + 0.5;
    if (yc <= y_low || yc >= y_high) continue;
    const int jw = ((j % ny) + ny) % ny;
    double q = 0;
    for (int k = 0; k < nz; ++k) {
      for (int di = 0; di <= 1; ++di) {
        const int i = ((i0 + di) % nx + nx) % nx;
        if (L.solid(i, jw, k)) continue;
        q += (di == 0 ? 1.0 - a : a) * solver.node_moments(i, jw, k).ux;
      }
    }
    p.y.push_back(yc - y_low);
    p.q.push_back(q);
  }
  // Trapezoids between the surfaces (q = 0) and the node values.
  double prev_y = 0, prev_q = 0;
  for (std::size_t n = 0; n <= p.y.size(); ++n) {
    const double y = n < p.y.size() ? p.y[n] : p.width;
    const double q = n < p.y.size() ? p.q[n] : 0.0;
    p.flux += 0.5 * (q + prev_q) * (y - prev_y);
    prev_y = y;
    prev_q = q;
  }
  return p;
}

double band_width(const GapProfile& p, double fraction) {
  assert(fraction >= 0 && fraction <= 1);
  const double target = fraction * p.flux;
  double prev_y = 0, prev_q = 0, acc = 0;
  for (std::size_t n = 0; n <= p.y.size(); ++n) {
    const double y = n < p.y.size() ? p.y[n] : p.width;
    const double q = n < p.y.size() ? p.q[n] : 0.0;
    const double h = y - prev_y;
    const double piece = 0.5 * (q + prev_q) * h;
    if (acc + piece >= target && piece > 0) {
      // q is linear on this piece: acc + q0 t + (q1 - q0) t^2 / (2h) = target; solve for t.
      const double need = target - acc;
      const double slope = (q - prev_q) / h;
      double t;
      if (std::abs(slope) < 1e-300) {
        t = need / prev_q;
      } else {
        t = (-prev_q + std::sqrt(prev_q * prev_q + 2.0 * slope * need)) / slope;
      }
      return prev_y + t;
    }
    acc += piece;
    prev_y = y;
    prev_q = q;
  }
  return p.width;
}

}  // namespace dld::fluid
