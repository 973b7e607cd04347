// SPDX-License-Identifier: MIT
#include "membrane/mesh_quality.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace dld::membrane {

MeshQuality mesh_quality(const TriMesh& mesh) {
  MeshQuality q;
  q.nodes = mesh.node_count();
  q.faces = mesh.face_count();
  q.min_angle_deg = 180.0;
  const Points& x = mesh.nodes;
  for (const Face& t : mesh.faces)
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d u = x.col(t[(k + 1) % 3]) - x.col(t[k]),
                      v = x.col(t[(k + 2) % 3]) - x.col(t[k]);
      double a = std::acos(std::clamp(u.dot(v) / (u.norm() * v.norm()), -1.0, 1.0)) * 180.0 / M_PI;
      q.min_angle_deg = std::min(q.min_angle_deg, a);
      q.max_angle_deg = std::max(q.max_angle_deg, a);
    }
  const auto e = edges(mesh);
  double s = 0.0, s2 = 0.0;
  q.edge_min = 1e300;
  std::vector<int> val(mesh.node_count(), 0);
  for (auto [i, j] : e) {
    double l = (x.col(i) - x.col(j)).norm();
    q.edge_min = std::min(q.edge_min, l);
    q.edge_max = std::max(q.edge_max, l);
    s += l;
    s2 += l * l;
    val[i]++;
    val[j]++;
  }
  q.edge_mean = s / e.size();
  q.edge_std_over_mean =
      std::sqrt(std::max(0.0, s2 / e.size() - q.edge_mean * q.edge_mean)) / q.edge_mean;
  for (int v : val) q.valence[v]++;
  q.area = surface_area(mesh);
  q.volume = enclosed_volume(mesh);
  return q;
}

std::string describe(const MeshQuality& q) {
  std::string vh;
  for (auto [v, n] : q.valence) vh += fmt::format(" {}:{}", v, n);
  return fmt::format(
      "{} nodes, {} faces; angles {:.1f}..{:.1f} deg; edges {:.4g}..{:.4g}, mean {:.4g}, std/mean "
      "{:.3f}; valence{}; area {:.6g}, volume {:.6g}",
      q.nodes, q.faces, q.min_angle_deg, q.max_angle_deg, q.edge_min, q.edge_max, q.edge_mean,
      q.edge_std_over_mean, vh, q.area, q.volume);
}

}  // namespace dld::membrane
