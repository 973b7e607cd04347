// SPDX-License-Identifier: MIT
// Box frame -> device frame (SPEC section 7): device paths are folded into the box with
// shared/dld_geometry's wrap_into_box and must come back unchanged.
#include "analysis/unwrap.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace dld::analysis {
namespace {

using P = std::array<double, 3>;

/// Samples a straight device path from a to b, folds it into the box, unwraps it and compares.
/// Returns the number of samples at which the box position jumped (a face was crossed).
int round_trip(const DldCell& cell, P a, P b, int samples = 400) {
  std::vector<P> device, box;
  for (int s = 0; s <= samples; ++s) {
    const double t = static_cast<double>(s) / samples;
    device.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), 2.4});
    box.push_back(wrap_into_box(cell, device.back()).position);
  }
  const auto back = unwrap_box_trajectory(cell, box);
  int jumps = 0;
  for (std::size_t i = 0; i < device.size(); ++i) {
    EXPECT_NEAR(back[i][0], device[i][0], 1e-9) << "sample " << i;
    EXPECT_NEAR(back[i][1], device[i][1], 1e-9) << "sample " << i;
    if (i > 0 && std::abs(box[i][0] - box[i - 1][0]) + std::abs(box[i][1] - box[i - 1][1]) >
                     0.5 * cell.lambda) {
      ++jumps;
    }
  }
  return jumps;
}

const DldCell kCell{32.0, 10.0, 4.8, 4.4};

TEST(Unwrap, XBoundaryForwardWithTheRowShift) {
  // Three columns at constant device y: each crossing lowers the box y by d.
  EXPECT_EQ(round_trip(kCell, {5, 16, 2.4}, {5 + 3 * 32.0, 16, 2.4}), 3);
}

TEST(Unwrap, XBoundaryBackward) {
  EXPECT_EQ(round_trip(kCell, {20, 16, 2.4}, {20 - 2.5 * 32.0, 16, 2.4}), 2);  // x = 0, -32
}

TEST(Unwrap, YBoundaryUpAndDown) {
  EXPECT_EQ(round_trip(kCell, {16, 3, 2.4}, {16, 3 + 2.2 * 32.0, 2.4}), 2);    // y = 32, 64
  EXPECT_EQ(round_trip(kCell, {16, 30, 2.4}, {16, 30 - 2.2 * 32.0, 2.4}), 2);  // y = 0, -32
}

TEST(Unwrap, BothBoundariesInBothDirections) {
  // Diagonal paths (4 or 5 x crossings and 2 or 3 y crossings, a few at the same sample); near
  // the bottom face the row shift of an x crossing also wraps y.
  EXPECT_GE(round_trip(kCell, {2, 1, 2.4}, {2 + 4 * 32.0, 1 + 3 * 32.0, 2.4}), 5);
  EXPECT_GE(round_trip(kCell, {30, 31, 2.4}, {30 - 4 * 32.0, 31 - 3 * 32.0, 2.4}), 5);
  EXPECT_GE(round_trip(kCell, {2, 31, 2.4}, {2 + 5 * 32.0, 31 - 2 * 32.0, 2.4}), 5);
  // Moving right at y just above 0: crossings in x alone wrap the box y through y = 0.
  EXPECT_GE(round_trip(kCell, {3, 1.0, 2.4}, {3 + 3 * 32.0, 1.0, 2.4}), 3);
}

TEST(Unwrap, FractionalShiftAndOtherLambda) {
  const DldCell cell{20.0, 6.0, 4.8, 1.7};
  EXPECT_GE(round_trip(cell, {1, 1, 2.4}, {1 + 6 * 20.0, 1 - 3 * 20.0, 2.4}), 9);
}

}  // namespace
}  // namespace dld::analysis
