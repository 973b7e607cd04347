// SPDX-License-Identifier: MIT
// Mesh quality figures reported for generated meshes.
#pragma once
#include <map>
#include <string>

#include "membrane/mesh.hpp"

namespace dld::membrane {

struct MeshQuality {
  int nodes = 0;
  int faces = 0;
  double min_angle_deg = 0.0;
  double max_angle_deg = 0.0;
  double edge_min = 0.0, edge_mean = 0.0, edge_max = 0.0;
  double edge_std_over_mean = 0.0;  ///< spread of edge lengths [-]
  std::map<int, int> valence;       ///< valence -> node count
  double area = 0.0, volume = 0.0;
};

MeshQuality mesh_quality(const TriMesh& mesh);
/// Several lines, for logs and docs.
std::string describe(const MeshQuality& q);

}  // namespace dld::membrane
