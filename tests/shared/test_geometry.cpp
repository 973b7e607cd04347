// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include "shared/dld_geometry.hpp"

namespace {

const dld::DldCell kCell{32.0, 10.0, 4.8, 4.4};

TEST(DldGeometry, PillarDistanceSeesShiftedImages) {
  EXPECT_NEAR(kCell.pillar_distance(16.0, 16.0), -10.0, 1e-12);
  EXPECT_NEAR(kCell.pillar_distance(16.0, 26.0), 0.0, 1e-12);
  // Just right of the box: the next column's pillar sits d higher.
  EXPECT_NEAR(kCell.pillar_distance(48.0, 16.0 + 4.4 + 10.0), 0.0, 1e-12);
  // Periodic in y: the pillar below seen from the top edge.
  EXPECT_NEAR(kCell.pillar_distance(16.0, 32.0 + 16.0 - 10.0), 0.0, 1e-12);
}

TEST(DldGeometry, WrapThroughShiftedXFace) {
  const auto w = dld::wrap_into_box(kCell, {33.0, 10.0, 1.0});
  EXPECT_NEAR(w.position[0], 1.0, 1e-12);
  EXPECT_NEAR(w.position[1], 10.0 - 4.4, 1e-12);
  EXPECT_EQ(w.crossings_x, 1);
  EXPECT_EQ(w.crossings_y, 0);
  const auto d = dld::device_position(kCell, w.position, w.crossings_x, w.crossings_y);
  EXPECT_NEAR(d[0], 33.0, 1e-12);
  EXPECT_NEAR(d[1], 10.0, 1e-12);
}

TEST(DldGeometry, WrapBothFacesBothDirectionsRoundTrips) {
  for (double x : {-70.0, -1.0, 5.0, 40.0, 100.0})
    for (double y : {-50.0, -0.5, 3.0, 31.9, 70.0}) {
      const auto w = dld::wrap_into_box(kCell, {x, y, 2.0});
      EXPECT_GE(w.position[0], 0.0);
      EXPECT_LT(w.position[0], 32.0);
      EXPECT_GE(w.position[1], 0.0);
      EXPECT_LT(w.position[1], 32.0);
      const auto d = dld::device_position(kCell, w.position, w.crossings_x, w.crossings_y);
      EXPECT_NEAR(d[0], x, 1e-12);
      EXPECT_NEAR(d[1], y, 1e-12);
    }
}

}  // namespace
