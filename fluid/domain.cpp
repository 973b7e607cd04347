// SPDX-License-Identifier: MIT
#include "fluid/domain.hpp"

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
