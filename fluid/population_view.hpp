// SPDX-License-Identifier: MIT
// Where the populations of the pull layout live in memory. The pull kernel leaves post(q, x), the
// post-collision population q of node x, at slot (q, x) = f[q n + x] of its destination array, and
// reads the *pull slot* (i, y - c_i) for population i of node y. The in-place (AA) update keeps one
// array in two alternating states (Bailey et al., Proc. ICPP 2009, 550):
//   swapped: post(q, x) at f[opp(q) n + x]          (the pull layout with the arrays relabelled)
//   shifted: post(q, x) at f[q n + x + offset(c_q)] (each value already at the node it streams to)
// In each state a pull-layout index (q, s) has one memory slot, base[q] + s, so bounce-back, the
// periodic ghosts and the moments use their pull-layout formulas through a view unchanged.
#pragma once
#include <array>
#include <cstddef>

#include "fluid/d3q19.hpp"
#include "fluid/lattice.hpp"

namespace dld::fluid {

enum class PopulationLayout { kPull, kSwapped, kShifted };

struct PopulationView {
  std::array<double*, D3Q19::q> base{};  ///< pull-layout (q, s) at base[q][s]

  PopulationView(const Lattice& L, double* f, PopulationLayout layout) {
    const std::size_t n = L.padded_size();
    for (int q = 0; q < D3Q19::q; ++q) {
      switch (layout) {
        case PopulationLayout::kPull:
          base[q] = f + q * n;
          break;
        case PopulationLayout::kSwapped:
          base[q] = f + D3Q19::opp[q] * n;
          break;
        case PopulationLayout::kShifted:
          base[q] = f + static_cast<std::ptrdiff_t>(q * n) + L.offset(q);
          break;
      }
    }
  }
  double& operator()(int q, std::size_t s) const { return base[q][s]; }
  /// Memory index (from `f`) of pull-layout index q n + s.
  std::size_t mapped(std::size_t pull_index, std::size_t n, const double* f) const {
    const std::size_t q = pull_index / n;
    return static_cast<std::size_t>(base[q] - f) + (pull_index - q * n);
  }
};

}  // namespace dld::fluid
