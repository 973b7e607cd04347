// SPDX-License-Identifier: MIT
#include "fluid/lattice.hpp"

#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dld::fluid {

Lattice::Lattice(Domain domain) : domain_(std::move(domain)) {
  padded_ = static_cast<std::size_t>(px()) * py() * pz();
  if (padded_ * D3Q19::q >= std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("lattice too large for 32-bit link indices");
  for (int i = 0; i < D3Q19::q; ++i)
    offsets_[i] = D3Q19::c[i][0] + static_cast<std::ptrdiff_t>(D3Q19::c[i][1]) * px() +
                  static_cast<std::ptrdiff_t>(D3Q19::c[i][2]) * px() * py();

  solid_.assign(padded_, 0);
  for (int k = -1; k <= nz(); ++k)
    for (int j = -1; j <= ny(); ++j)
      for (int i = -1; i <= nx(); ++i) solid_[index(i, j, k)] = domain_.solid_node(i, j, k) ? 1 : 0;

  // Ghost nodes are filled from interior nodes before bounce-back overwrites the slots of solid
  // ones. With a fractional shift the x ghosts interpolate between two nodes, which is only
  // meaningful if no solid node lies next to the x faces.
  if (domain_.shift != std::floor(domain_.shift)) {
    for (int k = 0; k < nz(); ++k)
      for (int j = -1; j <= ny(); ++j)
        for (int i : {-1, 0, nx() - 1, nx()})
          if (solid(i, j, k))
            throw std::invalid_argument(
                "a pillar touches the shifted x boundary: the shift must be a whole number of "
                "nodes");
  }

  for (int k = 0; k < nz(); ++k)
    for (int j = 0; j < ny(); ++j) {
      int i = 0;
      while (i < nx()) {
        while (i < nx() && solid(i, j, k)) ++i;
        int start = i;
        while (i < nx() && !solid(i, j, k)) ++i;
        if (i > start) {
          segments_.push_back({index(start, j, k), i - start});
          fluid_nodes_ += static_cast<std::size_t>(i - start);
        }
      }
    }

  for (int k = 0; k < nz(); ++k)
    for (int j = 0; j < ny(); ++j)
      for (int i = 0; i < nx(); ++i) {
        if (solid(i, j, k)) continue;
        std::size_t f = index(i, j, k);
        for (int q = 1; q < D3Q19::q; ++q) {
          std::size_t s = f - offsets_[q];  // the node this one pulls direction q from
          if (!solid_[s]) continue;
          // Wall planes are handled as whole-plane copies (apply_bounce_back), not links.
          if (domain_.walls_z && (k - D3Q19::c[q][2] < 0 || k - D3Q19::c[q][2] >= nz())) continue;
          const auto target = static_cast<std::uint32_t>(q * padded_ + s);
          const auto first = static_cast<std::uint32_t>(D3Q19::opp[q] * padded_ + f);
          if (!domain_.curved_walls) {
            links_.push_back({target, first});
            continue;
          }
          // The link from f towards the wall runs along c_opp(q) = -c_q.
          const double t =
              domain_.pillar_link_fraction(i + 0.5, j + 0.5, -D3Q19::c[q][0], -D3Q19::c[q][1]);
          const std::size_t behind =
              f + offsets_[q];  // f - c_opp(q), the next node away from the wall
          if (t < 0.5 && !solid_[behind]) {
            curved_links_.push_back({target, first,
                                     static_cast<std::uint32_t>(D3Q19::opp[q] * padded_ + behind),
                                     2.0 * t, 1.0 - 2.0 * t});
          } else if (t >= 0.5) {
            curved_links_.push_back({target, first, static_cast<std::uint32_t>(q * padded_ + f),
                                     0.5 / t, (2.0 * t - 1.0) / (2.0 * t)});
          } else {
            links_.push_back({target, first});  // too thin a gap to interpolate: plain bounce-back
          }
        }
      }
}

}  // namespace dld::fluid
