// SPDX-License-Identifier: MIT
#include "fluid/bounce_back.hpp"

#include <algorithm>

namespace dld::fluid {
namespace {

// Wall below plane k = 0 (sign +1: populations moving up are pulled from the ghost plane) or
// above plane k = nz-1 (sign -1). For each such direction q, the slots (q, f - c_q) of the whole
// ghost plane receive (opp q, f) for every node f of the adjacent plane: one contiguous copy.
// Rows are copied together with the ghost columns between them; those extra slots are pulled,
// in the linear index, only by ghost nodes, which are never updated.
// A moving wall adds 6 w_q rho0 (c_q . u_wall) to the reflected population (Ladd, J. Fluid Mech.
// 271 (1994) 285, eq. 5.2, with rho0 = 1): no mass is added for tangential wall motion.
void wall_plane(const Lattice& L, const PopulationView& v, int k, int sign,
                const std::array<double, 3>& uw) {
  const std::size_t first = L.index(0, 0, k);
  const std::size_t count = L.index(L.nx() - 1, L.ny() - 1, k) - first + 1;
  for (int q = 1; q < D3Q19::q; ++q) {
    if (D3Q19::c[q][2] != sign) continue;
    const double* src = v.base[D3Q19::opp[q]] + first;
    double* dst = v.base[q] + first - L.offset(q);
    const double du = 6.0 * D3Q19::w[q] *
                      (D3Q19::c[q][0] * uw[0] + D3Q19::c[q][1] * uw[1] + D3Q19::c[q][2] * uw[2]);
    if (du == 0.0) {
      std::copy(src, src + count, dst);
    } else {
      for (std::size_t m = 0; m < count; ++m) dst[m] = src[m] + du;
    }
  }
}

void wall_planes(const Lattice& lattice, const PopulationView& v) {
  if (!lattice.domain().walls_z) return;
  wall_plane(lattice, v, 0, +1, lattice.domain().wall_velocity_low);
  wall_plane(lattice, v, lattice.nz() - 1, -1, lattice.domain().wall_velocity_high);
}

}  // namespace

void apply_bounce_back(const Lattice& lattice, double* f) {
  apply_bounce_back(lattice, lattice.links(), lattice.curved_links(),
                    PopulationView(lattice, f, PopulationLayout::kPull), f);
}

BounceBackTables map_bounce_back(const Lattice& lattice, const PopulationView& v, const double* f) {
  const std::size_t n = lattice.padded_size();
  const auto at = [&](std::uint32_t i) { return static_cast<std::uint32_t>(v.mapped(i, n, f)); };
  BounceBackTables t;
  for (const BounceBackLink& l : lattice.links()) t.links.push_back({at(l.target), at(l.source)});
  for (const CurvedLink& l : lattice.curved_links())
    t.curved.push_back({at(l.target), at(l.first), at(l.second), l.a, l.b});
  return t;
}

void apply_bounce_back(const Lattice& lattice, std::span<const BounceBackLink> links,
                       std::span<const CurvedLink> curved, const PopulationView& v, double* f) {
  const std::size_t count = links.size();
#pragma omp parallel for schedule(static)
  for (std::size_t l = 0; l < count; ++l) f[links[l].target] = f[links[l].source];
  // Interpolated links return a f1 + b f2 where plain bounce-back returns f1: the difference is
  // mass created or lost at the wall every step, which accumulates over a long run. It is handed
  // back in equal parts to the same links, so the total is conserved to round-off.
  const std::size_t ncurved = curved.size();
  if (ncurved == 0) return wall_planes(lattice, v);
  double excess = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : excess)
  for (std::size_t l = 0; l < ncurved; ++l) {
    const double reflected = curved[l].a * f[curved[l].first] + curved[l].b * f[curved[l].second];
    f[curved[l].target] = reflected;
    excess += reflected - f[curved[l].first];
  }
  const double share = excess / static_cast<double>(ncurved);
#pragma omp parallel for schedule(static)
  for (std::size_t l = 0; l < ncurved; ++l) f[curved[l].target] -= share;
  wall_planes(lattice, v);
}

}  // namespace dld::fluid
