// SPDX-License-Identifier: MIT
#include "membrane/column_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dld::membrane {

std::string to_string(TransportMode m) {
  switch (m) {
    case TransportMode::kZigzag:
      return "zigzag";
    case TransportMode::kDisplacement:
      return "displacement";
    case TransportMode::kMixed:
      return "mixed";
    case TransportMode::kUndecided:
      break;
  }
  return "undecided";
}

ColumnTracker::ColumnTracker(double lambda_um, double row_shift_um,
                             std::vector<Eigen::Vector3d> starts)
    : lambda_(lambda_um),
      d_(row_shift_um),
      start_(std::move(starts)),
      now_(start_),
      y_after_first_(start_.size(), std::numeric_limits<double>::quiet_NaN()),
      x_after_first_(start_.size(), std::numeric_limits<double>::quiet_NaN()) {}

void ColumnTracker::update(const std::vector<Eigen::Vector3d>& centroids) {
  for (std::size_t k = 0; k < start_.size(); ++k) {
    const Eigen::Vector3d before = now_[k];
    now_[k] = centroids[k];
    // Where the cell crossed one column from its start (linear between samples).
    const double target = start_[k].x() + lambda_;
    if (std::isnan(y_after_first_[k]) && now_[k].x() >= target) {
      const double span = now_[k].x() - before.x();
      const double t = span > 0 ? std::clamp((target - before.x()) / span, 0.0, 1.0) : 1.0;
      y_after_first_[k] = before.y() + t * (now_[k].y() - before.y());
      x_after_first_[k] = target;
    }
  }
}

double ColumnTracker::fractional_columns(int k) const {
  return (now_[static_cast<std::size_t>(k)].x() - start_[static_cast<std::size_t>(k)].x()) /
         lambda_;
}

int ColumnTracker::columns(int k) const {
  return static_cast<int>(std::floor(fractional_columns(k)));
}

int ColumnTracker::min_columns() const {
  int c = std::numeric_limits<int>::max();
  for (int k = 0; k < cells(); ++k) c = std::min(c, columns(k));
  return cells() ? c : 0;
}

double ColumnTracker::shift_per_column(int k) const {
  const auto i = static_cast<std::size_t>(k);
  const double span = (now_[i].x() - x_after_first_[i]) / lambda_;
  if (std::isnan(y_after_first_[i]) || span < 1.0) return std::numeric_limits<double>::quiet_NaN();
  return (now_[i].y() - y_after_first_[i]) / span;
}

int ColumnTracker::columns_for_certainty() const {
  const int period = d_ > 0 ? static_cast<int>(std::ceil(lambda_ / d_ - 1e-9)) : 0;
  return std::max(5, period + 1);
}

TransportMode ColumnTracker::mode(int k) const {
  const double s = shift_per_column(k);
  if (std::isnan(s) || columns(k) < columns_for_certainty()) return TransportMode::kUndecided;
  if (std::abs(s - d_) < 0.25 * d_) return TransportMode::kDisplacement;
  if (std::abs(s) < 0.25 * d_) return TransportMode::kZigzag;
  return TransportMode::kMixed;
}

bool ColumnTracker::all_modes_certain() const {
  for (int k = 0; k < cells(); ++k) {
    const TransportMode m = mode(k);
    if (m != TransportMode::kZigzag && m != TransportMode::kDisplacement) return false;
  }
  return cells() > 0;
}

}  // namespace dld::membrane
