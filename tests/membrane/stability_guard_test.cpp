// SPDX-License-Identifier: MIT
// StabilityGuard: a healthy cell passes; a cell with a non-finite node, a volume out of its band,
// or a node pushed into the pillar or through a wall stops the run with a message naming the cell,
// the place and the step; the worst values over the run are kept for the summary.
#include "membrane/stability_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

const DldCell kBox{80.0, 25.0, 12.0, 11.0};  // lattice lengths; pillar centred at (40, 40)
constexpr double kDx = 0.4;                  // um per lattice length

struct Fixture {
  TriMesh ref = test::cell_mesh(300, 4.0);
  CellSet cells{ref, MembraneMechanics{}};
  Fixture() {
    cells.add_cell(Eigen::Vector3d(10.0, 10.0, 6.0));
    cells.add_cell(Eigen::Vector3d(10.0, 70.0, 6.0));
  }
  StabilityGuard guard() const {
    return StabilityGuard(kBox, kDx, GuardLimits{}, {cells.volume(0), cells.volume(1)});
  }
  std::string message(StabilityGuard& g) {
    try {
      g.check(cells, 1234, 5);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "";
  }
};

TEST(StabilityGuard, HealthyCellsPass) {
  Fixture f;
  auto g = f.guard();
  EXPECT_NO_THROW(g.check(f.cells, 10, 0));
  EXPECT_EQ(g.worst_volume_change(0), 0.0);
  EXPECT_EQ(g.worst_penetration_um(1), 0.0);
}

TEST(StabilityGuard, NonFiniteNodeNamesTheCellAndStep) {
  Fixture f;
  auto g = f.guard();
  f.cells.positions()(1, f.ref.node_count() + 3) = std::numeric_limits<double>::quiet_NaN();
  const auto m = f.message(g);
  EXPECT_NE(m.find("cell 6 has non-finite nodes at step 1234"), std::string::npos) << m;
}

TEST(StabilityGuard, VolumeOutOfBandNamesTheCellWhereAndWhen) {
  Fixture f;
  auto g = f.guard();
  const int n = f.ref.node_count();
  const Eigen::Vector3d c = f.cells.centroid(0);
  // Scale cell 0 about its centroid by 1.02 in every direction: +6 % volume.
  for (int i = 0; i < n; ++i)
    f.cells.positions().col(i) = c + 1.02 * (f.cells.positions().col(i) - c);
  const auto m = f.message(g);
  EXPECT_NE(m.find("cell 5 volume changed by +6.1 %"), std::string::npos) << m;
  EXPECT_NE(m.find("at step 1234, centroid (4.00, 4.00, 2.40) um"), std::string::npos) << m;
  EXPECT_NEAR(g.worst_volume_change(0), std::pow(1.02, 3) - 1, 1e-9);
}

TEST(StabilityGuard, NodeInsideThePillarOrAWallStopsTheRun) {
  Fixture f;
  const int n = f.ref.node_count();
  {
    auto g = f.guard();
    // Cell 0 (radius 4) moved right up against the pillar (surface at x = 15 on y = 40): its
    // rim reaches about 2 spacings (0.8 um) inside.
    const Eigen::Vector3d to(13.0, 40.0, 6.0);
    const Eigen::Vector3d by = to - f.cells.centroid(0);
    for (int i = 0; i < n; ++i) f.cells.positions().col(i) += by;
    const auto m = f.message(g);
    EXPECT_NE(m.find("cell 5 node"), std::string::npos) << m;
    EXPECT_NE(m.find("um inside the pillar or a wall at step 1234, node at ("), std::string::npos)
        << m;
  }
  {
    Fixture h;
    auto g = h.guard();
    // Cell 1 moved down until its lowest node is half a spacing below z = 0: kept, not fatal.
    auto translate = [&](const Eigen::Vector3d& by) {
      for (int i = n; i < 2 * n; ++i) h.cells.positions().col(i) += by;
    };
    translate(Eigen::Vector3d(0, 0, -h.cells.positions().middleCols(n, n).row(2).minCoeff() - 0.5));
    EXPECT_NO_THROW(g.check(h.cells, 1, 0));
    EXPECT_NEAR(g.worst_penetration_um(1), 0.5 * kDx, 1e-12);
    // Cell 1 one box on in x (and up by the shift), against the pillar of that box: found through
    // the shifted boundary (nodes are unwrapped, the pillar is the folded one).
    const Eigen::Vector3d c = h.cells.centroid(1);
    translate(Eigen::Vector3d(13.0 + 80.0, 40.0 + 11.0, 6.0) - c);
    std::string m;
    try {
      g.check(h.cells, 2, 0);
    } catch (const std::runtime_error& e) {
      m = e.what();
    }
    EXPECT_NE(m.find("cell 1 node"), std::string::npos) << m;
    EXPECT_NE(m.find("inside the pillar or a wall at step 2"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace dld::membrane
