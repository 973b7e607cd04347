// SPDX-License-Identifier: MIT
// restore_volume: a cell that lost volume (squeezed, dented) gets its rest volume back to
// round-off, far from the origin too, by a displacement along the volume's gradient (the smallest
// that does it: no tangential part, no net translation of a symmetric shape); a cell at its rest
// volume is left bit for bit.
#include "membrane/volume_correction.hpp"

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

TEST(VolumeCorrection, ALostVolumeComesBackToRoundOffByTheSmallestDisplacement) {
  const TriMesh ref = test::cell_mesh(500, 9.75);
  const double v0 = enclosed_volume(ref);
  // Far from the origin (a cell 20 columns downstream) and squeezed by 2 % along y: 2 % lost.
  Points x = test::perturbed(ref.nodes, 0.05, 7);
  x.row(1) *= 0.98;
  x.colwise() += Eigen::Vector3d(1600.0, -300.0, 6.0);
  const auto volume = [&](const Points& p) {  // about the centroid: no round-off from 1600
    return enclosed_volume(ref, p.colwise() - p.rowwise().mean());
  };
  const double lost = 1.0 - volume(x) / v0;
  ASSERT_GT(lost, 0.015);
  const Points before = x;
  const double given = restore_volume(x, ref.faces, v0);
  EXPECT_NEAR(given, lost, 1e-12);
  EXPECT_NEAR(volume(x) / v0, 1.0, 1e-12);
  EXPECT_LT((x.rowwise().mean() - before.rowwise().mean()).norm(), 1e-9) << "the centroid stays";
  // Along the gradient: node displacements of the order of lost V / area, none much larger.
  const double scale = lost * v0 / surface_area(ref, before);
  const Eigen::VectorXd moved = (x - before).colwise().norm();
  EXPECT_GT(moved.maxCoeff(), 0.2 * scale);
  EXPECT_LT(moved.maxCoeff(), 5.0 * scale);
  // The smallest displacement: any other that restores the volume as well is longer, e.g. the
  // uniform scaling about the centroid.
  const Eigen::Vector3d c = before.rowwise().mean();
  const double s = std::cbrt(v0 / volume(before));
  const Points scaled = ((before.colwise() - c) * s).colwise() + c;
  EXPECT_LT((x - before).norm(), (scaled - before).norm());
}

TEST(VolumeCorrection, ASymmetricShapeGrowsInPlaceAndARestingCellIsUntouched) {
  const TriMesh ref = test::cell_mesh(500, 9.75);
  const double v0 = enclosed_volume(ref);
  Points x = ref.nodes * 0.99;
  x.colwise() += Eigen::Vector3d(40.0, 40.0, 6.0);
  const Eigen::Vector3d c = x.rowwise().mean();
  restore_volume(x, ref.faces, v0);
  EXPECT_NEAR(enclosed_volume(ref, x) / v0, 1.0, 1e-12);
  EXPECT_LT((x.rowwise().mean() - c).norm(), 1e-9) << "no net translation";

  Points rest = ref.nodes;
  EXPECT_EQ(restore_volume(rest, ref.faces, enclosed_volume(ref, rest)), 0.0);
  EXPECT_TRUE(rest == ref.nodes) << "a cell at its rest volume moves not at all";
}

}  // namespace
}  // namespace dld::membrane
