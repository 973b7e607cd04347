// SPDX-License-Identifier: MIT
#include "membrane/taylor_deformation.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace dld::membrane {

InertiaEllipsoid inertia_ellipsoid(const TriMesh& mesh, const Points& x) {
  // Volume centroid about a nearby origin (the node mean) to keep round-off small.
  const Eigen::Vector3d o = x.rowwise().mean();
  double volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  for (const Face& f : mesh.faces) {
    const Eigen::Vector3d a = x.col(f[0]) - o, b = x.col(f[1]) - o, c = x.col(f[2]) - o;
    const double v = a.dot(b.cross(c)) / 6.0;
    volume += v;
    first += v * (a + b + c) / 4.0;  // tetrahedron (0, a, b, c): centroid (a + b + c)/4
  }
  InertiaEllipsoid e;
  e.volume = volume;
  e.centre = o + first / volume;
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const Face& f : mesh.faces) {
    const Eigen::Vector3d a = x.col(f[0]) - e.centre, b = x.col(f[1]) - e.centre,
                          c = x.col(f[2]) - e.centre;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d s = a + b + c;
    m += (v / 20.0) *
         (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m);  // ascending eigenvalues
  for (int i = 0; i < 3; ++i) {
    e.semi_axes(i) = std::sqrt(5.0 * std::max(eig.eigenvalues()(2 - i), 0.0) / volume);
    e.axes.col(i) = eig.eigenvectors().col(2 - i);
  }
  return e;
}

ShearPlaneShape shear_plane_shape(const InertiaEllipsoid& e, const Eigen::Vector3d& flow_axis,
                                  const Eigen::Vector3d& vorticity_axis) {
  int out = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(e.axes.col(i).dot(vorticity_axis)) > std::abs(e.axes.col(out).dot(vorticity_axis)))
      out = i;
  const int l = out == 0 ? 1 : 0;  // semi_axes descend: the first kept one is L
  const int b = out == 2 ? 1 : 2;
  ShearPlaneShape s;
  s.long_axis = e.semi_axes(l);
  s.short_axis = e.semi_axes(b);
  s.deformation = (s.long_axis - s.short_axis) / (s.long_axis + s.short_axis);
  const Eigen::Vector3d gradient = flow_axis.cross(vorticity_axis);
  const Eigen::Vector3d dir = e.axes.col(l);
  double angle = std::atan2(dir.dot(gradient), dir.dot(flow_axis));
  if (angle > M_PI / 2) angle -= M_PI;
  if (angle <= -M_PI / 2) angle += M_PI;
  s.inclination = angle;
  return s;
}

}  // namespace dld::membrane
