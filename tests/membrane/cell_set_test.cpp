// SPDX-License-Identifier: MIT
// CellSet, the API the coupler drives: forces of several cells equal the per-cell model forces
// (evaluated in parallel over cells), contact adds only where cells come close, nodes move by U dt.
#include "membrane/cell_set.hpp"

#include <gtest/gtest.h>

#include "shared/input_error.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

MembraneMechanics mechanics(const TriMesh& ref) {
  std::vector<AnyModel> m;
  m.emplace_back(SkalakModel(ref, {1e-3, 0.1}));
  m.emplace_back(BendingModel(ref, {1e-3}));
  m.emplace_back(VolumePenalty(ref, {1e-2}));
  return MembraneMechanics({"skalak", "bending", "volume"}, std::move(m));
}

TEST(CellSet, ForcesOfManyCellsAreThePerCellForces) {
  const TriMesh ref = test::cell_mesh(300, 5.0);
  CellSet cells(ref, mechanics(ref));
  const int n = ref.node_count();
  for (int k = 0; k < 5; ++k)
    cells.add_cell(test::perturbed(ref.nodes * (1.0 + 0.05 * k), 0.05, k));
  Points f;
  const double e = cells.compute_forces(f);
  ASSERT_EQ(f.cols(), 5 * n);
  double e_sum = 0.0;
  for (int k = 0; k < 5; ++k) {
    Points fk = Points::Zero(3, n);
    e_sum += cells.mechanics().add_forces(cells.cell_positions(k), fk);
    EXPECT_LT((f.middleCols(k * n, n) - fk).norm(), 1e-14 * fk.norm()) << k;
  }
  EXPECT_NEAR(e, e_sum, 1e-12 * e_sum);
  EXPECT_NEAR(e, cells.energy(), 1e-12 * e_sum);
}

TEST(CellSet, ContactActsOnlyBetweenCloseCells) {
  const TriMesh ref = test::cell_mesh(300, 5.0);
  const DldCell box{80.0, 25.0, 12.0, 11.0};
  CellSet cells(ref, mechanics(ref), Contact(box, ContactParams{1.0, 1e-3, true, true, true}));
  const double half = cells.reference().nodes.row(0).maxCoeff();
  cells.add_cell(Eigen::Vector3d(10.0, 5.0, 6.0));
  cells.add_cell(Eigen::Vector3d(10.0 + 2 * half + 0.5, 5.0, 6.0));  // 0.5 apart: in range
  cells.add_cell(Eigen::Vector3d(60.0, 70.0, 6.0));                  // far from all
  Points f;
  cells.compute_forces(f);
  const int n = ref.node_count();
  // Rest shapes: only contact acts. The first two cells are pushed apart along x, the third not.
  EXPECT_LT(f.middleCols(0, n).rowwise().sum()(0), 0.0);
  EXPECT_GT(f.middleCols(n, n).rowwise().sum()(0), 0.0);
  EXPECT_LT(f.middleCols(2 * n, n).norm(), 1e-12);
}

TEST(CellSet, MoveAddsVelocityTimesStep) {
  const TriMesh ref = test::octahedron();
  CellSet cells(ref, MembraneMechanics{});
  cells.add_cell(Eigen::Vector3d(1.0, 2.0, 3.0));
  const Points x0 = cells.positions();
  std::vector<double> u(3 * ref.node_count(), 0.0);
  for (std::size_t i = 0; i < u.size(); i += 3) u[i] = 2.0;
  cells.move(u, 0.25);
  EXPECT_LT((cells.positions().row(0).array() - x0.row(0).array() - 0.5).abs().maxCoeff(), 1e-15);
  EXPECT_EQ(cells.flat_positions().size(), u.size());
  EXPECT_EQ(cells.flat_positions()[0], cells.positions()(0, 0));
  u.pop_back();
  EXPECT_THROW(cells.move(u, 0.25), InputError);
}

}  // namespace
}  // namespace dld::membrane
