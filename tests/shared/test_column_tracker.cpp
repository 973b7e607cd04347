// SPDX-License-Identifier: MIT
// Columns passed and the mode rule of shared/column_tracker.hpp on synthetic centroid paths.
#include <gtest/gtest.h>

#include <cmath>

#include "shared/column_tracker.hpp"

namespace dld {
namespace {

constexpr double kLambda = 32.0;

/// Moves one cell along x by `columns` columns in `samples` steps, y = y0 + slope * (x - x0).
ColumnTracker follow(double d, double slope, double columns, int samples = 400) {
  const Eigen::Vector3d start(3.0, 1.0, 2.4);
  ColumnTracker t(kLambda, d, {start});
  for (int s = 1; s <= samples; ++s) {
    const double dx = columns * kLambda * s / samples;
    t.update({Eigen::Vector3d(start.x() + dx, start.y() + slope * dx, 2.4)});
  }
  return t;
}

TEST(ColumnTracker, CountsWholeColumnsFromTheCellsOwnStart) {
  const ColumnTracker t = follow(4.4, 0.0, 3.5);
  EXPECT_EQ(t.columns(0), 3);
  EXPECT_NEAR(t.fractional_columns(0), 3.5, 1e-12);
  EXPECT_EQ(t.min_columns(), 3);
}

TEST(ColumnTracker, OneRowShiftPerColumnIsDisplacement) {
  const ColumnTracker t = follow(4.4, 4.4 / kLambda, 10);
  EXPECT_NEAR(t.shift_per_column(0), 4.4, 1e-9);
  EXPECT_EQ(t.mode(0), TransportMode::kDisplacement);
  EXPECT_TRUE(t.all_modes_certain());
}

TEST(ColumnTracker, NoNetDriftIsZigzag) {
  const ColumnTracker t = follow(6.0, 0.0, 8);
  EXPECT_NEAR(t.shift_per_column(0), 0.0, 1e-12);
  EXPECT_EQ(t.mode(0), TransportMode::kZigzag);
}

TEST(ColumnTracker, HalfARowShiftIsNotCertainAndEndsMixed) {
  const ColumnTracker t = follow(6.0, 2.8 / kLambda, 8);
  EXPECT_EQ(t.mode(0), TransportMode::kZigzag);  // the nearer one
  EXPECT_FALSE(t.certain(0));
  EXPECT_FALSE(t.all_modes_certain());
  EXPECT_EQ(t.final_mode(0), TransportMode::kMixed);
  // Within d/5 of a mode it is certain.
  EXPECT_TRUE(follow(6.0, 5.0 / kLambda, 8).certain(0));
  EXPECT_FALSE(follow(6.0, 4.7 / kLambda, 8).certain(0));
}

TEST(ColumnTracker, ShiftIsTakenAtWholeColumnsNotAtTheCurrentPhase) {
  // Displacement in steps: y jumps by d in the middle of each column. Sampled half-way through a
  // column the current y is half a step ahead; the whole-column crossings are not.
  const Eigen::Vector3d start(0.0, 0.0, 2.4);
  ColumnTracker t(kLambda, 4.4, {start});
  for (int s = 1; s <= 1000; ++s) {
    const double x = 9.6 * kLambda * s / 1000;
    const double c = std::floor(x / kLambda + 0.5);  // jumps at half columns
    t.update({Eigen::Vector3d(x, 4.4 * c, 2.4)});
  }
  EXPECT_NEAR(t.shift_per_column(0), 4.4, 1e-9);
}

TEST(ColumnTracker, UndecidedBeforeOneZigzagPeriod) {
  // d = 2 um: a zigzag period is lambda/d = 16 columns, so 17 are needed.
  EXPECT_EQ(follow(2.0, 2.0 / kLambda, 16.5).mode(0), TransportMode::kUndecided);
  EXPECT_EQ(follow(2.0, 2.0 / kLambda, 17.5).mode(0), TransportMode::kDisplacement);
  EXPECT_EQ(follow(6.0, 0.0, 4.5).mode(0), TransportMode::kUndecided);  // at least 5 columns
}

TEST(ColumnTracker, FirstColumnTransientIsLeftOut) {
  // A cell pushed up by 5 um in its first column, then moving horizontally: zigzag.
  const Eigen::Vector3d start(0.0, 0.0, 2.4);
  ColumnTracker t(kLambda, 4.4, {start});
  for (int s = 1; s <= 1000; ++s) {
    const double x = 10.0 * kLambda * s / 1000;
    t.update({Eigen::Vector3d(x, x < kLambda ? 5.0 * x / kLambda : 5.0, 2.4)});
  }
  EXPECT_NEAR(t.shift_per_column(0), 0.0, 1e-9);
  EXPECT_EQ(t.mode(0), TransportMode::kZigzag);
}

}  // namespace
}  // namespace dld
