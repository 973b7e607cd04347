// SPDX-License-Identifier: MIT
#include "fluid/periodic_ghosts.hpp"

#include <cmath>
#include <vector>

namespace dld::fluid {
namespace {

std::vector<int> directions_with(int axis, int sign) {
  std::vector<int> out;
  for (int i = 0; i < D3Q19::q; ++i)
    if (D3Q19::c[i][axis] == sign) out.push_back(i);
  return out;
}

int wrap(int j, int n) {
  return ((j % n) + n) % n;
}

}  // namespace

void fill_periodic_ghosts(const Lattice& L, double* f) {
  fill_periodic_ghosts(L, PopulationView(L, f, PopulationLayout::kPull));
}

void fill_periodic_ghosts(const Lattice& L, const PopulationView& v) {
  static const std::vector<int> up_y = directions_with(1, +1), down_y = directions_with(1, -1);
  static const std::vector<int> up_x = directions_with(0, +1), down_x = directions_with(0, -1);
  static const std::vector<int> up_z = directions_with(2, +1), down_z = directions_with(2, -1);
  const int nx = L.nx(), ny = L.ny(), nz = L.nz();

  // y: row -1 is row ny-1 (pulled by populations moving up), row ny is row 0.
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i) {
      for (int q : up_y) v.base[q][L.index(i, -1, k)] = v.base[q][L.index(i, ny - 1, k)];
      for (int q : down_y) v.base[q][L.index(i, ny, k)] = v.base[q][L.index(i, 0, k)];
    }

  // x: ghost (-1, j) holds what left through x = nx at height j + shift; ghost (nx, j) holds
  // node (0, j - shift). Rows j = -1 and ny are included so diagonal pulls see the same images.
  const double d = L.domain().shift;
  const double d_floor = std::floor(d);
  const int di = static_cast<int>(d_floor);
  const double a = d - d_floor;  // interpolation weight of the upper source node
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = -1; j <= ny; ++j) {
      const std::size_t gl = L.index(-1, j, k), gr = L.index(nx, j, k);
      // Left ghost: sample column nx-1 at j + d = (j + di) + a.
      const std::size_t l0 = L.index(nx - 1, wrap(j + di, ny), k);
      const std::size_t l1 = L.index(nx - 1, wrap(j + di + 1, ny), k);
      // Right ghost: sample column 0 at j - d = (j - di - 1) + (1 - a).
      const std::size_t r0 = L.index(0, wrap(j - di - 1, ny), k);
      const std::size_t r1 = L.index(0, wrap(j - di, ny), k);
      if (a == 0.0) {
        for (int q : up_x) v.base[q][gl] = v.base[q][l0];
        for (int q : down_x) v.base[q][gr] = v.base[q][r1];
      } else {
        for (int q : up_x) v.base[q][gl] = (1.0 - a) * v.base[q][l0] + a * v.base[q][l1];
        for (int q : down_x) v.base[q][gr] = a * v.base[q][r0] + (1.0 - a) * v.base[q][r1];
      }
    }

  if (!L.domain().walls_z) {
    // z: whole planes, ghosts of x and y included.
#pragma omp parallel for schedule(static)
    for (int j = -1; j <= ny; ++j)
      for (int i = -1; i <= nx; ++i) {
        for (int q : up_z) v.base[q][L.index(i, j, -1)] = v.base[q][L.index(i, j, nz - 1)];
        for (int q : down_z) v.base[q][L.index(i, j, nz)] = v.base[q][L.index(i, j, 0)];
      }
  }
}

}  // namespace dld::fluid
