// SPDX-License-Identifier: MIT
// A deformed cell relaxes back to its rest shape without fluid (overdamped dynamics); the volume
// penalty keeps the volume within 0.1 %.
#include <gtest/gtest.h>

#include "membrane/mesh_quality.hpp"
#include "membrane/relaxation.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

TEST(Relaxation, StretchedCellReturnsToRestShape) {
  const TriMesh ref = test::cell_mesh(500, 9.75);  // r = 3.9 um at dx = 0.4 um
  const double ks = 1e-3;
  std::vector<AnyModel> models;
  models.emplace_back(SkalakModel(ref, {ks, 100 * ks}));
  models.emplace_back(BendingModel(ref, {2.5e-3 * ks * 9.75 * 9.75}));
  models.emplace_back(VolumePenalty(ref, {1000 * ks / 9.75}));
  CellSet cells(ref, MembraneMechanics({"skalak", "bending", "volume"}, std::move(models)));
  Points x = cells.reference().nodes;
  x.row(0) *= 1.2;
  x.row(1) /= 1.2;
  x.row(2) *= 0.9;  // also 10 % volume loss, so the volume penalty has work to do
  cells.add_cell(x);
  const double v0 = enclosed_volume(cells.reference());
  const double dev0 = (cells.positions() - cells.reference().nodes).colwise().norm().maxCoeff();
  RelaxOptions o;
  o.mobility = 1.0 / ks;
  o.time_step = 0.05;
  o.max_steps = 20000;
  o.force_tolerance = 1e-7 * ks;
  const double e0 = cells.energy();
  const RelaxResult r = relax_overdamped(cells, o);
  const Points rel = cells.positions().colwise() - cells.centroid(0);
  const double dev = (rel - cells.reference().nodes).colwise().norm().maxCoeff();
  const double drift = cells.volume(0) / v0 - 1.0;
  const double edge = mesh_quality(cells.reference()).edge_mean;
  std::printf(
      "relaxed in %d steps: energy %.3g -> %.3g, largest node offset %.3g -> %.3g dx (mean edge "
      "%.3g dx), "
      "volume drift %.2e\n",
      r.steps, e0, r.energy, dev0, dev, edge, drift);
  // Overdamped descent is slow on the soft bending/shear modes; "back at rest" here means the
  // elastic energy fell by four orders and no node is further than 5 % of an edge from its rest
  // place.
  EXPECT_LT(r.energy, 1e-4 * e0);
  EXPECT_LT(dev, 0.05 * edge);
  EXPECT_LT(std::abs(drift), 1e-3);
}

}  // namespace
}  // namespace dld::membrane
