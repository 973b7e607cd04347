// SPDX-License-Identifier: MIT
#include "analysis/unwrap.hpp"

#include <cmath>

namespace dld::analysis {

std::vector<std::array<double, 3>> unwrap_box_trajectory(
    const DldCell& cell, const std::vector<std::array<double, 3>>& box) {
  std::vector<std::array<double, 3>> out;
  out.reserve(box.size());
  int kx = 0, ky = 0;
  for (const auto& p : box) {
    if (!out.empty()) {
      const auto& prev = out.back();
      // x first: a crossing in x also moves the frame by d, which the y count must not see as a
      // y crossing (SPEC section 2: x is shifted periodic).
      kx += static_cast<int>(
          std::lround((prev[0] - device_position(cell, p, kx, ky)[0]) / cell.lambda));
      ky += static_cast<int>(
          std::lround((prev[1] - device_position(cell, p, kx, ky)[1]) / cell.lambda));
    }
    out.push_back(device_position(cell, p, kx, ky));
  }
  return out;
}

}  // namespace dld::analysis
