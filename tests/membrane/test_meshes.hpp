// SPDX-License-Identifier: MIT
// Shared helpers of the membrane tests: cached cell meshes and small hand-made meshes.
#pragma once
#include <random>

#include "membrane/mesh.hpp"
#include "membrane/mesh_cache.hpp"

namespace dld::membrane::test {

/// Evans-Fung cell of radius r (lattice units) with about `faces` faces, from the build's cache.
inline TriMesh cell_mesh(int faces, double radius = 9.75) {
  EvansFungShape s;
  s.radius = radius;
  TriMesh m = evans_fung_mesh(s, faces, "cache/meshes");
  m.nodes.colwise() -= centroid(m.nodes);
  return m;
}

/// Regular octahedron (closed, outward).
inline TriMesh octahedron() {
  TriMesh m;
  m.nodes.resize(3, 6);
  m.nodes << 1, -1, 0, 0, 0, 0, 0, 0, 1, -1, 0, 0, 0, 0, 0, 0, 1, -1;
  m.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

/// The nodes moved by uniform random offsets of size `amplitude`.
inline Points perturbed(const Points& x, double amplitude, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  Points y = x;
  for (int i = 0; i < y.size(); ++i) y.data()[i] += u(rng);
  return y;
}

}  // namespace dld::membrane::test
