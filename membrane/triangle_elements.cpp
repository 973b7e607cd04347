// SPDX-License-Identifier: MIT
#include "membrane/triangle_elements.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "shared/input_error.hpp"

namespace dld::membrane {

std::vector<TriangleReference> triangle_references(const TriMesh& reference,
                                                   const std::string& model) {
  std::vector<TriangleReference> out;
  out.reserve(reference.faces.size());
  for (std::size_t f = 0; f < reference.faces.size(); ++f) {
    const Face& t = reference.faces[f];
    const Eigen::Vector3d a = reference.nodes.col(t[1]) - reference.nodes.col(t[0]);
    const Eigen::Vector3d b = reference.nodes.col(t[2]) - reference.nodes.col(t[0]);
    const Eigen::Vector3d n = a.cross(b);
    const double scale = std::max(a.squaredNorm(), b.squaredNorm());
    if (!(n.norm() > 1e-10 * scale))
      throw InputError(
          fmt::format("{} model: reference face {} is degenerate (zero area)", model, f));
    // Local frame: ex along the first edge, ey in the plane.
    const Eigen::Vector3d ex = a.normalized();
    const Eigen::Vector3d ey = n.normalized().cross(ex);
    Eigen::Matrix2d m;
    m << a.dot(ex), b.dot(ex), a.dot(ey), b.dot(ey);
    out.push_back({t, m.inverse(), 0.5 * n.norm()});
  }
  return out;
}

}  // namespace dld::membrane
