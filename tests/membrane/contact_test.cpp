// SPDX-License-Identifier: MIT
// Contact repulsion: force is minus the gradient of the contact energy, pairs across the periodic
// y and shifted-periodic x boundaries are found, cell-cell forces balance, walls and pillar push
// nodes away.
#include "membrane/contact.hpp"

#include <gtest/gtest.h>

#include <random>

#include "shared/input_error.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

const DldCell kBox{80.0, 25.0, 12.0, 11.0};  // lattice units: lambda, R, H, d

Contact make(bool walls, bool pillar, bool cells) {
  return Contact(kBox, ContactParams{1.0, 1e-3, walls, pillar, cells});
}

TEST(Contact, PairAcrossShiftedPeriodicX) {
  // (79.7, y) is the same as (-0.3, y - d): 0.5 from a node at (0.2, y - d).
  Points x(3, 2);
  x << 0.2, 79.7, 5.0, 5.0 + kBox.shift, 6.0, 6.0;
  Points f = Points::Zero(3, 2);
  const Contact c = make(false, false, true);
  c.add_forces(x, 1, f);
  EXPECT_EQ(c.last_pair_count(), 1);
  EXPECT_GT(f(0, 0), 0.0);  // pushed to +x, away from the image at x = -0.3
  EXPECT_NEAR(f(1, 0), 0.0, 1e-12 * f(0, 0));
  EXPECT_NEAR((f.col(0) + f.col(1)).norm(), 0.0, 1e-15);
  // Without the shift the nodes are d apart in y and do not interact.
  x(1, 1) = 5.0;
  f.setZero();
  c.add_forces(x, 1, f);
  EXPECT_EQ(c.last_pair_count(), 0);
}

TEST(Contact, PairAcrossPeriodicYAndCorner) {
  Points x(3, 2);
  x << 10.0, 10.0, 0.3, 79.9, 6.0, 6.0;
  Points f = Points::Zero(3, 2);
  const Contact c = make(false, false, true);
  c.add_forces(x, 1, f);
  EXPECT_EQ(c.last_pair_count(), 1);
  EXPECT_GT(f(1, 0), 0.0);
  // Corner: (79.8, 79.8) wraps to (-0.2, 79.8 - d) in x, so place the partner there.
  x << 0.1, 79.8, 79.8 - kBox.shift, 79.8, 6.0, 6.0;
  f.setZero();
  c.add_forces(x, 1, f);
  EXPECT_EQ(c.last_pair_count(), 1);
}

TEST(Contact, NodesOfOneCellDoNotRepel) {
  Points x(3, 2);
  x << 10.0, 10.3, 10.0, 10.0, 6.0, 6.0;
  Points f = Points::Zero(3, 2);
  make(false, false, true).add_forces(x, 2, f);
  EXPECT_EQ(f.norm(), 0.0);
}

TEST(Contact, WallsAndPillarPushAway) {
  Points x(3, 3);
  x << 5.0, 5.0, 40.0 + 25.5, 5.0, 5.0, 40.0, 0.4, 11.7, 6.0;
  Points f = Points::Zero(3, 3);
  make(true, true, false).add_forces(x, 1, f);
  EXPECT_GT(f(2, 0), 0.0);  // bottom wall pushes up
  EXPECT_LT(f(2, 1), 0.0);  // top wall pushes down
  EXPECT_GT(f(0, 2), 0.0);  // pillar (centre 40, 40, radius 25) pushes out along +x
  EXPECT_NEAR(f(1, 2), 0.0, 1e-6 * f(0, 2));
}

TEST(Contact, ForceIsMinusGradientOfEnergy) {
  // Two coarse cells face to face 0.6 apart, near the bottom wall and across the x boundary.
  const TriMesh cell = test::cell_mesh(300, 5.0);
  const int n = cell.node_count();
  Points x(3, 2 * n);
  const double half = cell.nodes.row(0).maxCoeff();
  x.leftCols(n) = cell.nodes.colwise() + Eigen::Vector3d(79.0 - half, 20.0, 2.0);
  x.rightCols(n) =
      cell.nodes.colwise() + Eigen::Vector3d(79.6 + half - 80.0, 20.0 - kBox.shift, 2.1);
  const Contact c = make(true, true, true);
  Points f = Points::Zero(3, 2 * n);
  c.add_forces(x, n, f);
  ASSERT_GT(c.last_pair_count(), 0);
  ASSERT_GT(f.norm(), 0.0);
  Points fd(3, 2 * n);
  const double h = 1e-6;
  for (int i = 0; i < x.size(); ++i) {
    Points xp = x, xm = x;
    xp.data()[i] += h;
    xm.data()[i] -= h;
    fd.data()[i] = -(c.energy(xp, n) - c.energy(xm, n)) / (2 * h);
  }
  const double rel = (f - fd).norm() / f.norm();
  std::printf("contact: %ld pairs, |F + grad E_fd| / |F| = %.2e\n", c.last_pair_count(), rel);
  EXPECT_LT(rel, 1e-6);
  // Cell-cell forces alone balance.
  Points fc = Points::Zero(3, 2 * n);
  make(false, false, true).add_forces(x, n, fc);
  EXPECT_LT(fc.rowwise().sum().norm(), 1e-12 * fc.colwise().norm().sum());
}

/// `cells` "cells" of `per` nodes each within 3 lattice lengths of a random centre in the box.
Points random_cells(std::mt19937_64& rng, int cells, int per) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Points x(3, cells * per);
  for (int k = 0; k < cells; ++k) {
    const Eigen::Vector3d c(80.0 * u(rng), 80.0 * u(rng), 2.0 + 8.0 * u(rng));
    for (int i = 0; i < per; ++i)
      x.col(k * per + i) = c + Eigen::Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * 3.0;
  }
  return x;
}

TEST(Contact, NeighbourListGivesTheForcesOfAFreshSearchAsNodesMove) {
  // 150 "cells" of 8 nodes at random in a thin slab (many pairs, many across the periodic and
  // shifted faces). One Contact object is reused while the nodes drift (its neighbour list is
  // rebuilt only when some node moved more than skin / 2); a fresh object searches anew each time.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int cells = 150, per = 8, n = cells * per;
  Points x = random_cells(rng, cells, per);
  const Contact reused = make(true, true, true);
  long pairs_seen = 0;
  for (int step = 0; step < 40; ++step) {
    for (int i = 0; i < n; ++i)
      x.col(i) += Eigen::Vector3d(u(rng) - 0.3, u(rng) - 0.5, u(rng) - 0.5) * 0.08;
    if (step == 20) x.middleCols(5 * per, per).row(0).array() += 80.0;  // a cell one box on
    Points fa = Points::Zero(3, n), fb = Points::Zero(3, n);
    const double ea = reused.add_forces(x, per, fa);
    const Contact fresh = make(true, true, true);
    const double eb = fresh.add_forces(x, per, fb);
    ASSERT_EQ(reused.last_pair_count(), fresh.last_pair_count()) << "step " << step;
    EXPECT_LE((fa - fb).cwiseAbs().maxCoeff(), 1e-12 * fb.cwiseAbs().maxCoeff()) << step;
    EXPECT_NEAR(ea, eb, 1e-12 * std::abs(eb)) << step;
    pairs_seen += fresh.last_pair_count();
  }
  EXPECT_GT(pairs_seen, 40 * 40) << "the test must exercise many pairs";
}

// Issue 14: the cells split over processes, each seeing the others' cells as ghosts, get the
// forces of one process holding all cells, bit for bit, over drifting steps (lists reused and
// rebuilt); without the ghosts the forces differ.
TEST(Contact, GhostsOfOtherProcessesGiveTheOneProcessForcesBitForBit) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int cells = 60, per = 8, n = cells * per;
  Points x = random_cells(rng, cells, per);
  const Contact whole = make(true, true, true);
  const std::vector<int> firsts{0, 7, 25, 26, 60};  // four processes, one with a single cell
  std::vector<Contact> part(firsts.size() - 1, make(true, true, true));
  long ghost_pairs = 0;
  for (int step = 0; step < 20; ++step) {
    for (int i = 0; i < n; ++i)
      x.col(i) += Eigen::Vector3d(u(rng) - 0.3, u(rng) - 0.5, u(rng) - 0.5) * 0.08;
    Points f = Points::Zero(3, n);
    whole.add_forces(x, per, f);
    for (std::size_t p = 0; p + 1 < firsts.size(); ++p) {
      const int a = firsts[p], b = firsts[p + 1];
      ContactGhosts g{a, {}, Points(3, 0)};
      for (int k = 0; k < cells; ++k)
        if (k < a || k >= b) g.cells.push_back(k);
      g.x.resize(3, per * std::ssize(g.cells));
      for (std::size_t j = 0; j < g.cells.size(); ++j)
        g.x.middleCols(static_cast<Eigen::Index>(j) * per, per) =
            x.middleCols(g.cells[j] * per, per);
      Points own = x.middleCols(a * per, (b - a) * per), fp = Points::Zero(3, own.cols());
      part[p].add_forces(own, per, fp, &g);
      ASSERT_EQ((fp - f.middleCols(a * per, (b - a) * per)).cwiseAbs().maxCoeff(), 0.0)
          << "process " << p << " step " << step;
      ghost_pairs += part[p].last_ghost_pair_count();
      Points alone = Points::Zero(3, own.cols());
      make(true, true, true).add_forces(own, per, alone);
      if (step == 0 && p == 0) {
        EXPECT_GT((alone - fp).cwiseAbs().maxCoeff(), 0.0);
      }
    }
  }
  EXPECT_GT(ghost_pairs, 100) << "the test must exercise pairs across processes";
}

TEST(Contact, RefusesBadParameters) {
  EXPECT_THROW(Contact(kBox, ContactParams{0.0, 1.0}), InputError);
  EXPECT_THROW(Contact(kBox, ContactParams{1.0, -1.0}), InputError);
  EXPECT_THROW(Contact(kBox, ContactParams{30.0, 1.0}), InputError);
}

}  // namespace
}  // namespace dld::membrane
