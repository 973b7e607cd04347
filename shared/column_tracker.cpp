// SPDX-License-Identifier: MIT
#include "shared/column_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dld {

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
      crossing_y_(start_.size()) {}

void ColumnTracker::update(const std::vector<Eigen::Vector3d>& centroids) {
  for (std::size_t k = 0; k < start_.size(); ++k) {
    const Eigen::Vector3d before = now_[k];
    now_[k] = centroids[k];
    // Where the cell crossed whole columns (linear between samples; a cell moving back and forth
    // records each column once, the first time).
    auto& ys = crossing_y_[k];
    while (true) {
      const double target = start_[k].x() + static_cast<double>(ys.size() + 1) * lambda_;
      if (now_[k].x() < target) {
        break;
      }
      const double span = now_[k].x() - before.x();
      const double t = span > 0 ? std::clamp((target - before.x()) / span, 0.0, 1.0) : 1.0;
      ys.push_back(before.y() + t * (now_[k].y() - before.y()));
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
  for (int k = 0; k < cells(); ++k) {
    c = std::min(c, columns(k));
  }
  return cells() ? c : 0;
}

double ColumnTracker::shift_per_column(int k) const {
  const auto& ys = crossing_y_[static_cast<std::size_t>(k)];
  if (ys.size() < 2) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return (ys.back() - ys.front()) / static_cast<double>(ys.size() - 1);
}

int ColumnTracker::columns_for_certainty() const {
  const int period = d_ > 0 ? static_cast<int>(std::ceil(lambda_ / d_ - 1e-9)) : 0;
  return std::max(5, period + 1);
}

TransportMode ColumnTracker::mode(int k) const {
  const double s = shift_per_column(k);
  if (std::isnan(s) || columns(k) < columns_for_certainty()) {
    return TransportMode::kUndecided;
  }
  return std::abs(s - d_) < std::abs(s) ? TransportMode::kDisplacement : TransportMode::kZigzag;
}

bool ColumnTracker::certain(int k) const {
  const TransportMode m = mode(k);
  if (m == TransportMode::kUndecided) {
    return false;
  }
  const double target = m == TransportMode::kDisplacement ? d_ : 0.0;
  return std::abs(shift_per_column(k) - target) < 0.2 * d_;
}

TransportMode ColumnTracker::final_mode(int k) const {
  if (mode(k) == TransportMode::kUndecided) {
    return TransportMode::kUndecided;
  }
  return certain(k) ? mode(k) : TransportMode::kMixed;
}

bool ColumnTracker::all_modes_certain() const {
  for (int k = 0; k < cells(); ++k) {
    if (!certain(k)) {
      return false;
    }
  }
  return cells() > 0;
}

}  // namespace dld
