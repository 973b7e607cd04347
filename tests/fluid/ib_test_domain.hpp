// SPDX-License-Identifier: MIT
// The small DLD-like lattice of the immersed-boundary tests and markers scattered over it.
#pragma once
#include <cmath>
#include <random>
#include <vector>

#include "fluid/lattice.hpp"

namespace dld::fluid::test {

/// 24 x 20 x 10 nodes, walls in z, one pillar of radius 4 at (12, 10); shifted x face.
inline Domain test_domain(double shift) {
  Domain d;
  d.nx = 24;
  d.ny = 20;
  d.nz = 10;
  d.shift = shift;
  d.walls_z = true;
  d.pillars.push_back({12.0, 10.0, 4.0});
  return d;
}

/// Markers anywhere outside the pillar of test_domain(shift): across both faces, by the walls.
inline std::vector<double> markers_everywhere(const Lattice& L, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-30.0, 50.0), uy(-25.0, 45.0), uz(0.3, 9.7);
  std::vector<double> pos;
  while (pos.size() < 3 * static_cast<std::size_t>(count)) {
    const double p[3] = {ux(rng), uy(rng), uz(rng)};
    const double x = std::fmod(std::fmod(p[0], 24.0) + 24.0, 24.0);
    const double y = p[1] - std::floor(p[0] / 24.0) * L.domain().shift;
    if (!L.domain().in_pillar(x, y)) pos.insert(pos.end(), p, p + 3);
  }
  return pos;
}

}  // namespace dld::fluid::test
