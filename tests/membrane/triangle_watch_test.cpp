// SPDX-License-Identifier: MIT
// TriangleWatch: the smallest triangle area ratio per cell, now and over the run, and one warning
// per cell when it first goes below Skalak's peak 1/sqrt(3).
#include "membrane/triangle_watch.hpp"

#include <gtest/gtest.h>

#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

TEST(TriangleWatch, ACellSqueezedPastSkalaksPeakIsNamedOnceAndItsSmallestKept) {
  const TriMesh ref = test::cell_mesh(300, 4.0);
  CellSet cells{ref, MembraneMechanics{}};
  cells.add_cell(Eigen::Vector3d(10.0, 10.0, 6.0));
  cells.add_cell(Eigen::Vector3d(10.0, 70.0, 6.0));
  TriangleWatch watch(ref);
  EXPECT_EQ(watch.worst_cell_now(), -1);
  // Before any update (a run shorter than one sample ends with its summary): 1, as at rest.
  EXPECT_EQ(watch.now(1), 1.0);
  EXPECT_EQ(watch.smallest(1), 1.0);
  EXPECT_TRUE(watch.update(cells, 100, 5).empty());
  EXPECT_NEAR(watch.now(0), 1.0, 1e-12);
  EXPECT_NEAR(watch.now(1), 1.0, 1e-12);

  // Cell 1 squeezed to half its width along x: a triangle's area ratio is between 0.5 (lying in a
  // plane with the x axis) and 1 (normal along x); the cell's flat faces come close to 0.5.
  const Points rest = cells.cell_positions(1);
  const Eigen::Vector3d c = cells.centroid(1);
  auto squeezed = cells.positions().middleCols(ref.node_count(), ref.node_count());
  squeezed.row(0) = (rest.row(0).array() - c.x()) * 0.5 + c.x();
  auto w = watch.update(cells, 200, 5);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("cell 6 "), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("step 200"), std::string::npos) << w[0];
  EXPECT_GE(watch.now(1), 0.5 - 1e-12);
  EXPECT_LT(watch.now(1), TriangleWatch::kSkalakPeak);
  EXPECT_EQ(watch.worst_cell_now(), 1);
  EXPECT_NEAR(watch.now(0), 1.0, 1e-12);

  // Still squeezed: no second warning. Back at rest: the smallest over the run is kept.
  EXPECT_TRUE(watch.update(cells, 300, 5).empty());
  const double least = watch.now(1);
  squeezed = rest;
  EXPECT_TRUE(watch.update(cells, 400, 5).empty());
  EXPECT_NEAR(watch.now(1), 1.0, 1e-12);
  EXPECT_EQ(watch.smallest(1), least);
}

}  // namespace
}  // namespace dld::membrane
