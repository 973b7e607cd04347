// SPDX-License-Identifier: MIT
#include "fluid/domain.hpp"

#include <algorithm>
#include <cmath>

namespace dld::fluid {

bool Domain::in_pillar(double x, double y) const {
  for (const Pillar& p : pillars) {
    for (int ix = -1; ix <= 1; ++ix) {
      // The image one box to the right sits `shift` higher (shifted periodic x).
      double cx = p.x + ix * nx;
      double dy = y - (p.y + ix * shift);
      dy -= ny * std::round(dy / ny);
      if ((x - cx) * (x - cx) + dy * dy < p.radius * p.radius) return true;
    }
  }
  return false;
}

bool Domain::solid_node(int i, int j, int k) const {
  if (walls_z && (k < 0 || k >= nz)) return true;
  return in_pillar(i + 0.5, j + 0.5);
}

double Domain::pillar_link_fraction(double x, double y, int cx, int cy) const {
  double best = 2.0;
  if (cx == 0 && cy == 0) return 0.5;
  for (const Pillar& p : pillars)
    for (int ix = -1; ix <= 1; ++ix)
      for (int iy = -1; iy <= 1; ++iy) {
        // |(x, y) + t (cx, cy) - centre|^2 = R^2: smallest root in (0, 1].
        const double ox = x - (p.x + ix * nx), oy = y - (p.y + ix * shift + iy * ny);
        const double a = cx * cx + cy * cy, b = 2.0 * (ox * cx + oy * cy);
        const double c = ox * ox + oy * oy - p.radius * p.radius;
        const double disc = b * b - 4.0 * a * c;
        if (disc < 0) continue;
        const double t = (-b - std::sqrt(disc)) / (2.0 * a);
        if (t > 0.0 && t <= 1.0) best = std::min(best, t);
      }
  return best <= 1.0 ? best : 0.5;
}

Domain dld_domain(const DldCell& cell_lu, int nx, int ny, int nz) {
  Domain d;
  d.nx = nx;
  d.ny = ny;
  d.nz = nz;
  d.shift = cell_lu.shift;
  d.walls_z = true;
  d.pillars.push_back({cell_lu.pillar_x(), cell_lu.pillar_y(), cell_lu.radius});
  return d;
}

}  // namespace dld::fluid
