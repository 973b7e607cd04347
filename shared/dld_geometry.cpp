// SPDX-License-Identifier: MIT
#include "shared/dld_geometry.hpp"

#include <cmath>

namespace dld {

double DldCell::pillar_distance(double x, double y) const {
  // Nearest image in y; in x the neighbouring columns' pillars are shifted by +-d in y.
  double best = 1e300;
  for (int ix = -1; ix <= 1; ++ix) {
    double cx = pillar_x() + ix * lambda;
    double cy0 = pillar_y() + ix * shift;
    double dy = y - cy0;
    dy -= lambda * std::round(dy / lambda);
    double r = std::hypot(x - cx, dy) - radius;
    best = std::min(best, r);
  }
  return best;
}

bool DldCell::pillar_within(double x, double y, double range) const {
  const double reach = radius + range;
  for (int ix = -1; ix <= 1; ++ix) {
    double dy = y - (pillar_y() + ix * shift);
    dy -= lambda * std::round(dy / lambda);  // the image pillar_distance uses
    if (std::abs(x - (pillar_x() + ix * lambda)) < reach && std::abs(dy) < reach) return true;
  }
  return false;
}

Wrapped wrap_into_box(const DldCell& cell, std::array<double, 3> p) {
  Wrapped w{p, 0, 0};
  auto& q = w.position;
  while (q[0] >= cell.lambda) {
    q[0] -= cell.lambda;
    q[1] -= cell.shift;
    ++w.crossings_x;
  }
  while (q[0] < 0.0) {
    q[0] += cell.lambda;
    q[1] += cell.shift;
    --w.crossings_x;
  }
  double ky = std::floor(q[1] / cell.lambda);
  q[1] -= ky * cell.lambda;
  if (q[1] >= cell.lambda) {  // round-off at the upper edge
    q[1] -= cell.lambda;
    ky += 1;
  }
  w.crossings_y = static_cast<int>(ky);
  return w;
}

std::array<double, 3> device_position(const DldCell& cell, const std::array<double, 3>& box, int kx,
                                      int ky) {
  return {box[0] + kx * cell.lambda, box[1] + kx * cell.shift + ky * cell.lambda, box[2]};
}

}  // namespace dld
