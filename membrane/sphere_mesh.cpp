// SPDX-License-Identifier: MIT
#include "membrane/sphere_mesh.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <utility>

#include "shared/input_error.hpp"

namespace dld::membrane {

TriMesh icosphere(int subdivisions, double radius) {
  if (subdivisions < 0 || subdivisions > 7)
    throw InputError(
        fmt::format("icosphere: subdivisions must be in [0, 7], got {}", subdivisions));
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InputError(fmt::format("icosphere: radius must be positive, got {}", radius));
  // The icosahedron: corners (0, +-1, +-t), (+-1, +-t, 0), (+-t, 0, +-1), t the golden ratio.
  const double t = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<Eigen::Vector3d> p{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                 {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                 {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Face> faces{{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                          {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                          {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                          {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& q : p) q.normalize();
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      const int id = static_cast<int>(p.size()) - 1;
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<Face> next;
    next.reserve(4 * faces.size());
    for (const Face& f : faces) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    faces = std::move(next);
  }
  TriMesh mesh;
  mesh.nodes.resize(3, static_cast<Eigen::Index>(p.size()));
  for (std::size_t i = 0; i < p.size(); ++i)
    mesh.nodes.col(static_cast<Eigen::Index>(i)) = radius * p[i];
  mesh.faces = std::move(faces);
  // The corner list above is counter-clockwise seen from outside; checked, not assumed.
  if (enclosed_volume(mesh) < 0.0)
    for (Face& f : mesh.faces) std::swap(f[1], f[2]);
  return mesh;
}

int icosphere_subdivisions(int target_faces) {
  int best = 0;
  for (int n = 1; n <= 7; ++n)
    if (std::abs(std::log(20.0 * std::pow(4.0, n) / std::max(target_faces, 20))) <
        std::abs(std::log(20.0 * std::pow(4.0, best) / std::max(target_faces, 20))))
      best = n;
  return best;
}

}  // namespace dld::membrane
