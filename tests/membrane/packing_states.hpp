// SPDX-License-Identifier: MIT
// The study's five initial states (SPEC section 6) from a scene file: each is packed (no cache),
// then checked against the geometry: every node gap above the scene's contact range and the
// haematocrit, computed from the meshes, within 1 percentage point of the study's value; cells
// stay flat and keep their volume.
#pragma once
#include <gtest/gtest.h>

#include <array>
#include <ostream>

#include "membrane/membrane_scene.hpp"

namespace dld::membrane::test {

struct StudyState {
  int cells;
  double ht_percent;
};
inline void PrintTo(const StudyState& s, std::ostream* os) {
  *os << s.cells << " cells, Ht " << s.ht_percent << " %";
}
inline constexpr std::array<StudyState, 5> kStudyStates{
    {{3, 8.0}, {6, 16.1}, {12, 32.2}, {15, 40.2}, {17, 45.6}}};

inline void check_study_state(const std::string& scene_file, StudyState s) {
  const Scene scene = load_scene(scene_file, false);
  MembraneScene m = read_membrane_scene(scene);
  ASSERT_TRUE(m.pack && m.contact);
  m.pack->cache = "";  // pack now, whatever a previous run saved
  const CachedPacking p = packed_scene_cells(m, scene, s.cells);
  const int n = p.cells.nodes_per_cell;
  ASSERT_EQ(p.cells.positions.cols(), static_cast<long>(s.cells) * n);
  CellSet cells(m.reference_lu, MembraneMechanics{});
  for (int k = 0; k < s.cells; ++k) cells.add_cell(Points(p.cells.positions.middleCols(k * n, n)));
  const DldCell box = scene.cell_lu();
  const Clearances g = clearances(cells.positions(), n, box, box.lambda);
  const double range = m.contact->range;  // lattice lengths
  EXPECT_GT(g.cells, range) << s.cells << " cells";
  EXPECT_GT(g.walls, range) << s.cells << " cells";
  EXPECT_GT(g.pillar, range) << s.cells << " cells";
  EXPECT_EQ(nodes_inside_other_cells(cells.positions(), m.reference_lu.faces, n, box), 0);
  // Flat: the depth (4.8 um) lets a rest-shape cell tilt about 11 degrees at most.
  EXPECT_LT(largest_tilt_deg(cells.positions(), n), 15.0) << s.cells << " cells";
  // Cell centroids lie in the box; the volume stayed that of the rest shape.
  const double v0 = enclosed_volume(m.reference_lu);
  for (int k = 0; k < s.cells; ++k) {
    const Eigen::Vector3d c = cells.centroid(k);
    EXPECT_TRUE(c.x() >= 0 && c.x() < box.lambda && c.y() >= 0 && c.y() < box.lambda) << k;
    EXPECT_NEAR(cells.volume(k) / v0, 1.0, 0.01) << k;
  }
  EXPECT_NEAR(100.0 * haematocrit(cells, box), s.ht_percent, 1.0) << s.cells << " cells";
}

}  // namespace dld::membrane::test
