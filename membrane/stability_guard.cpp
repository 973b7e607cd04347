// SPDX-License-Identifier: MIT
#include "membrane/stability_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dld::membrane {

StabilityGuard::StabilityGuard(const DldCell& box_lu, double dx_um, GuardLimits limits,
                               std::vector<double> v0)
    : box_(box_lu),
      dx_um_(dx_um),
      limits_(limits),
      v0_(std::move(v0)),
      worst_volume_(v0_.size(), 0.0),
      worst_depth_(v0_.size(), 0.0) {}

void StabilityGuard::check(const CellSet& cells, std::int64_t step, int first_cell) {
  const int n = cells.nodes_per_cell();
  const Points& x = cells.positions();
  auto where = [&](const Eigen::Vector3d& p) {
    return fmt::format("({:.2f}, {:.2f}, {:.2f}) um", p.x() * dx_um_, p.y() * dx_um_,
                       p.z() * dx_um_);
  };
  for (int k = 0; k < cells.cell_count(); ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const Eigen::Vector3d c = cells.centroid(k);
    const double v = cells.volume(k);
    if (!std::isfinite(v) || !c.allFinite() ||
        !x.middleCols(static_cast<Eigen::Index>(k) * n, n).allFinite()) {
      throw std::runtime_error(
          fmt::format("unstable: cell {} has non-finite nodes at step {}", first_cell + k, step));
    }
    const double dv = v / v0_[kk] - 1.0;
    worst_volume_[kk] = std::max(worst_volume_[kk], std::abs(dv));
    if (std::abs(dv) > limits_.volume_change) {
      throw std::runtime_error(
          fmt::format("unstable: cell {} volume changed by {:+.1f} % (limit {:.1f} %) at step {}, "
                      "centroid {}",
                      first_cell + k, 100 * dv, 100 * limits_.volume_change, step, where(c)));
    }
    double deepest = 0;
    int node = -1;
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d p = x.col(static_cast<Eigen::Index>(k) * n + i);
      const auto w = wrap_into_box(box_, {p.x(), p.y(), p.z()}).position;
      // Only a positive depth counts: far from the pillar its (negative) term cannot be it.
      const double in_pillar =
          box_.pillar_within(w[0], w[1], 0.0) ? -box_.pillar_distance(w[0], w[1]) : -1.0;
      const double depth = std::max({in_pillar, -w[2], w[2] - box_.depth});
      if (depth > deepest) {
        deepest = depth, node = i;
      }
    }
    worst_depth_[kk] = std::max(worst_depth_[kk], deepest);
    if (deepest > limits_.penetration) {
      throw std::runtime_error(fmt::format(
          "unstable: cell {} node {} is {:.2f} um inside the pillar or a wall at step {}, node at "
          "{}",
          first_cell + k, node, deepest * dx_um_, step,
          where(x.col(static_cast<Eigen::Index>(k) * n + node))));
    }
  }
}

}  // namespace dld::membrane
