// SPDX-License-Identifier: MIT
// CGAL-made Evans-Fung meshes: face count, area and volume against quadrature and the published
// values (../shared/reference/README.md), closed and outward, quality, and the disk cache.
#include <gtest/gtest.h>

#include <filesystem>

#include "membrane/evans_fung.hpp"
#include "membrane/mesh_quality.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

TEST(EvansFung, QuadratureMatchesPublishedValues) {
  // Reference README: R = 3.9 um with (0.207, 2.000, -1.123) gives area 133.30 um^2,
  // volume 93.22 um^3, maximum thickness 2.555 um, centre thickness 0.807 um.
  EvansFungShape s;
  s.radius = 3.9;
  EXPECT_NEAR(s.area(), 133.30, 0.01);
  EXPECT_NEAR(s.volume(), 93.22, 0.01);
  EXPECT_NEAR(s.max_thickness(), 2.555, 0.001);
  EXPECT_NEAR(2.0 * s.half_thickness(0.0), 0.807, 0.001);
}

void check_cell_mesh(int faces, double tolerance) {
  SCOPED_TRACE(faces);
  const double r = 3.9;  // um
  EvansFungShape s;
  s.radius = r;
  const TriMesh m = evans_fung_mesh(s, faces, "cache/meshes");
  EXPECT_NO_THROW(validate_closed_surface(m, "test"));
  EXPECT_NEAR(m.face_count(), faces, 0.1 * faces);
  const MeshQuality q = mesh_quality(m);
  std::printf("%d faces requested: %s\n", faces, describe(q).c_str());
  EXPECT_NEAR(q.area / s.area(), 1.0, tolerance);
  EXPECT_NEAR(q.volume / s.volume(), 1.0, tolerance);
  EXPECT_GT(q.volume, 0.0);  // outward
  EXPECT_GT(q.min_angle_deg, 20.0);
  EXPECT_LT(q.edge_std_over_mean, 0.25);
  // Every node on the surface: implicit function near zero relative to R^2.
  for (int i = 0; i < m.node_count(); ++i)
    ASSERT_NEAR(s.implicit(m.nodes(0, i), m.nodes(1, i), m.nodes(2, i)) / (r * r), 0.0, 1e-8)
        << i << ": " << m.nodes.col(i).transpose();
  // Thickness and diameter of the mesh.
  EXPECT_NEAR(m.nodes.row(0).maxCoeff() - m.nodes.row(0).minCoeff(), 2 * r, tolerance * 2 * r);
  EXPECT_NEAR(m.nodes.row(2).maxCoeff() - m.nodes.row(2).minCoeff(), s.max_thickness(),
              tolerance * 2 * r);
}

TEST(CellMesh, TwoThousandFacesMatchQuadratureWithinOnePercent) {
  check_cell_mesh(2000, 0.01);
}

TEST(CellMesh, CoarseAndFineFaceCounts) {
  // Coarser meshes cut more volume off at the rim and the dimple (chords inside a convex
  // profile): measured -3.8 % at 500 faces and -6.1 % at 300 faces, against -0.9 % at 2000.
  check_cell_mesh(500, 0.05);
  check_cell_mesh(300, 0.07);
  check_cell_mesh(8000, 0.01);
}

TEST(CellMesh, CacheReturnsTheSameMesh) {
  const std::string dir = "cache/meshes-cache-test";
  std::filesystem::remove_all(dir);
  EvansFungShape s;
  s.radius = 2.0;
  const TriMesh a = evans_fung_mesh(s, 300, dir);
  EvansFungShape s2 = s;
  s2.radius = 4.0;
  const TriMesh b = evans_fung_mesh(s2, 300, dir);  // read back and scaled
  EXPECT_TRUE(std::filesystem::exists(std::filesystem::path(dir) / mesh_cache_name(s, 300)));
  ASSERT_EQ(a.node_count(), b.node_count());
  ASSERT_EQ(a.faces, b.faces);
  EXPECT_LT((2.0 * a.nodes - b.nodes).cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace dld::membrane
