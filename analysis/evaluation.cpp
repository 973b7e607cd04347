// SPDX-License-Identifier: MIT
#include "analysis/evaluation.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dld::analysis {

std::optional<double> y_at_advance(const CellTrack& cell, double advance_um) {
  const auto& p = cell.position;
  if (p.empty()) {
    return std::nullopt;
  }
  const double target = p.front()[0] + advance_um;
  if (p.front()[0] >= target) {
    return p.front()[1];
  }
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (p[i][0] < target) {
      continue;
    }
    // First sample at or past the target; the one before is below it, so the span is > 0.
    const double t = (target - p[i - 1][0]) / (p[i][0] - p[i - 1][0]);
    return p[i - 1][1] + t * (p[i][1] - p[i - 1][1]);
  }
  return std::nullopt;
}

double max_advance_columns(const CellTrack& cell, double lambda_um) {
  double best = 0;
  for (const auto& q : cell.position) {
    best = std::max(best, q[0] - cell.position.front()[0]);
  }
  return best / lambda_um;
}

double zigzag_failure(double y0, double y_end, int n, double lambda_um) {
  return (y_end - y0) / (n * lambda_um);
}

double displacement_failure(double y0, double y_end, int n, double lambda_um, double d_um) {
  return -(y_end - (y0 + n * d_um)) / (n * lambda_um);
}

std::optional<double> failure_probability(TransportMode expected, double y0, double y_end, int n,
                                          double lambda_um, double d_um) {
  if (expected == TransportMode::kZigzag) {
    return zigzag_failure(y0, y_end, n, lambda_um);
  }
  if (expected == TransportMode::kDisplacement) {
    return displacement_failure(y0, y_end, n, lambda_um, d_um);
  }
  return std::nullopt;
}

CellResult evaluate_cell(const CellTrack& cell, double lambda_um, double d_um, int pillars,
                         TransportMode expected) {
  CellResult r;
  r.id = cell.id;
  r.x0 = cell.position.front()[0];
  r.y0 = cell.position.front()[1];
  r.advance = max_advance_columns(cell, lambda_um);
  r.columns = static_cast<int>(std::floor(r.advance));
  r.pillars = std::min(pillars, r.columns);
  if (r.pillars >= 1) {
    // Exists: the cell advanced at least `pillars` columns.
    r.y_end = *y_at_advance(cell, r.pillars * lambda_um);
    r.p_f = failure_probability(expected, r.y0, r.y_end, r.pillars, lambda_um, d_um);
  }
  const auto vec = [](const std::array<double, 3>& q) { return Eigen::Vector3d(q[0], q[1], q[2]); };
  ColumnTracker tracker(lambda_um, d_um, {vec(cell.position.front())});
  for (std::size_t i = 1; i < cell.position.size(); ++i) {
    tracker.update({vec(cell.position[i])});
  }
  r.shift_per_column = tracker.shift_per_column(0);
  r.mode = tracker.final_mode(0);
  return r;
}

Stats mean_std(const std::vector<double>& v) {
  Stats s;
  s.n = static_cast<int>(v.size());
  if (v.empty()) {
    return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(), 0};
  }
  for (double x : v) {
    s.mean += x;
  }
  s.mean /= s.n;
  if (s.n < 2) {
    s.std = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  double ss = 0;
  for (double x : v) {
    ss += (x - s.mean) * (x - s.mean);
  }
  s.std = std::sqrt(ss / (s.n - 1));
  return s;
}

}  // namespace dld::analysis
