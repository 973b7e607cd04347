// SPDX-License-Identifier: MIT
// CGAL lives here only. Pipeline: (1) CGAL::make_surface_mesh on the implicit Evans-Fung function
// with fine criteria, giving an accurate but irregular surface; (2)
// Polygon_mesh_processing::isotropic_remeshing to the edge length h that an equilateral mesh
// of the target face count would have, h = sqrt(4 A / (sqrt(3) F)), corrected once or twice
// from the count obtained; (3) Newton projection of every node onto the exact surface.
#include "membrane/cgal_mesher.hpp"

#include <CGAL/Complex_2_in_triangulation_3.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

using Tr = CGAL::Surface_mesh_default_triangulation_3;
using C2t3 = CGAL::Complex_2_in_triangulation_3<Tr>;
using GT = Tr::Geom_traits;
using Point = GT::Point_3;
using FT = GT::FT;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

struct ImplicitShape {
  EvansFungShape shape;
  FT operator()(const Point& p) const { return shape.implicit(p.x(), p.y(), p.z()); }
};

SurfaceMesh initial_mesh(const EvansFungShape& s, double size) {
  Tr tr;
  C2t3 c2t3(tr);
  const double bound = 1.2 * s.radius;
  CGAL::Implicit_surface_3<GT, ImplicitShape> surface(
      ImplicitShape{s}, GT::Sphere_3(CGAL::ORIGIN, bound * bound), 1e-8);
  // angle bound [deg], radius bound of surface Delaunay balls, centre-surface distance bound.
  CGAL::Surface_mesh_default_criteria_3<Tr> criteria(30.0, size, 0.02 * size);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_tag());
  SurfaceMesh sm;
  CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, sm);
  return sm;
}

/// Newton steps along the gradient of the implicit function onto its zero level set.
Eigen::Vector3d project(const EvansFungShape& s, Eigen::Vector3d p) {
  const double h = 1e-7 * s.radius;
  for (int it = 0; it < 30; ++it) {
    const double f = s.implicit(p.x(), p.y(), p.z());
    Eigen::Vector3d g(
        (s.implicit(p.x() + h, p.y(), p.z()) - s.implicit(p.x() - h, p.y(), p.z())) / (2 * h),
        (s.implicit(p.x(), p.y() + h, p.z()) - s.implicit(p.x(), p.y() - h, p.z())) / (2 * h),
        (s.implicit(p.x(), p.y(), p.z() + h) - s.implicit(p.x(), p.y(), p.z() - h)) / (2 * h));
    const double g2 = g.squaredNorm();
    if (g2 == 0.0) break;
    Eigen::Vector3d step = f * g / g2;
    const double cap = 0.05 * s.radius;  // never jump across the thin centre
    if (step.norm() > cap) step *= cap / step.norm();
    p -= step;
    if (step.norm() < 1e-13 * s.radius) break;
  }
  return p;
}

TriMesh to_trimesh(const SurfaceMesh& sm, const EvansFungShape& s) {
  TriMesh m;
  std::vector<int> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), -1);
  m.nodes.resize(3, sm.number_of_vertices());
  int k = 0;
  for (auto v : sm.vertices()) {
    const Point& p = sm.point(v);
    m.nodes.col(k) = project(s, Eigen::Vector3d(p.x(), p.y(), p.z()));
    index[v.idx()] = k++;
  }
  for (auto f : sm.faces()) {
    Face t{};
    int c = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) t[c++] = index[v.idx()];
    m.faces.push_back(t);
  }
  if (enclosed_volume(m) < 0.0)
    for (Face& t : m.faces) std::swap(t[1], t[2]);
  return m;
}

}  // namespace

TriMesh mesh_evans_fung_cgal(const EvansFungShape& shape, int target_faces) {
  if (target_faces < 100 || target_faces > 50000)
    throw InputError(fmt::format("mesh face count {} is outside [100, 50000]", target_faces));
  // CGAL's default generator is seeded from the clock (initial surface points, remeshing): a
  // fixed seed makes the mesh a function of its parameters, as the cache key assumes.
  CGAL::get_default_random() = CGAL::Random(1972);
  const double area = shape.area();
  double h = std::sqrt(4.0 * area / (std::sqrt(3.0) * target_faces));
  // The fine initial surface is what isotropic remeshing projects onto.
  const SurfaceMesh fine = initial_mesh(shape, 0.4 * h);
  SurfaceMesh best;
  double best_err = 1e300;
  for (int attempt = 0; attempt < 4; ++attempt) {
    SurfaceMesh sm = fine;
    PMP::isotropic_remeshing(faces(sm), h, sm, CGAL::parameters::number_of_iterations(6));
    sm.collect_garbage();
    const double err = std::abs(static_cast<double>(sm.number_of_faces()) / target_faces - 1.0);
    if (err < best_err) {
      best_err = err;
      best = sm;
    }
    if (err < 0.02) break;
    h *= std::sqrt(static_cast<double>(sm.number_of_faces()) / target_faces);
  }
  return to_trimesh(best, shape);
}

}  // namespace dld::membrane
