// SPDX-License-Identifier: MIT
// The in-place update's layouts of FluidSolver (fluid/population_view.hpp): entering it from the
// pull layout, leaving it for a caller that writes populations, and the pull-layout copy that
// checkpoints store.
#include <algorithm>
#include <cstring>

#include "fluid/fluid_solver.hpp"

namespace dld::fluid {

// Swapped is the pull layout with arrays q and opp(q) exchanged; opp(q) = q + 1 for odd q.
void FluidSolver::relabel_pull_as_swapped() {
  const std::size_t n = lattice_.padded_size();
  double* f = f_.data();
  for (int q = 1; q < D3Q19::q; q += 2)
    std::swap_ranges(f + q * n, f + (q + 1) * n, f + (q + 1) * n);
  layout_ = PopulationLayout::kSwapped;
}

void FluidSolver::to_pull_layout() {
  if (layout_ == PopulationLayout::kPull) return;
  if (layout_ == PopulationLayout::kSwapped) {
    relabel_pull_as_swapped();  // the same exchange undoes it
  } else {
    const std::vector<double> pull = pull_populations();
    std::copy(pull.begin(), pull.end(), f_.begin());
  }
  layout_ = PopulationLayout::kPull;
}

std::vector<double> FluidSolver::pull_populations() const {
  std::vector<double> pull(f_.begin(), f_.end());
  if (layout_ == PopulationLayout::kPull) return pull;
  const std::size_t n = lattice_.padded_size();
  const PopulationView v(lattice_, const_cast<double*>(f_.data()), layout_);
  for (int q = 0; q < D3Q19::q; ++q) {
    if (layout_ == PopulationLayout::kSwapped) {
      std::memcpy(pull.data() + q * n, v.base[q], n * sizeof(double));
      continue;
    }
    // Shifted by offset(c_q): slots mapped outside the array (ghost slots at its two ends, which
    // no step reads before refilling them) are left as they are.
    const std::ptrdiff_t shift = lattice_.offset(q);
    const std::size_t lo = shift < 0 ? static_cast<std::size_t>(-shift) : 0;
    const std::size_t hi = shift > 0 ? n - static_cast<std::size_t>(shift) : n;
    std::memcpy(pull.data() + q * n + lo, v.base[q] + lo, (hi - lo) * sizeof(double));
  }
  return pull;
}

const BounceBackTables& FluidSolver::bounce_back_tables(PopulationLayout layout) {
  std::unique_ptr<BounceBackTables>& t =
      layout == PopulationLayout::kSwapped ? swapped_links_ : shifted_links_;
  if (!t) {
    t = std::make_unique<BounceBackTables>(
        map_bounce_back(lattice_, PopulationView(lattice_, f_.data(), layout), f_.data()));
  }
  return *t;
}

}  // namespace dld::fluid
