// SPDX-License-Identifier: MIT
// Watches a coupled run's cells so that an unstable run stops at once with a message naming the
// cell, where it is and the step (issue 5: hard cases), instead of running on into garbage; the
// last checkpoint written before then stays the last good one. Also keeps, per cell, the largest
// volume change and the deepest node inside the pillar or a wall over the run, for the summary.
// Units: positions and box in lattice lengths; messages in um.
#pragma once
#include <cstdint>
#include <vector>

#include "membrane/cell_set.hpp"
#include "shared/dld_geometry.hpp"

namespace dld::membrane {

struct GuardLimits {
  double volume_change = 0.05;  ///< |V/V0 - 1| that stops the run (the study asks for < 1 %)
  /// Depth [lattice lengths] of a node inside the pillar or a wall that stops the run: contact
  /// keeps nodes about one spacing away, so a node a whole spacing inside means the cell broke
  /// through.
  double penetration = 1.0;
};

class StabilityGuard {
 public:
  StabilityGuard(const DldCell& box_lu, double dx_um, GuardLimits limits, std::vector<double> v0);

  /// Throws std::runtime_error naming the cell (its global index: first_cell + k), the position
  /// [um, device frame] and the step when a limit is passed or a node is not finite.
  void check(const CellSet& cells, std::int64_t step, int first_cell);

  double worst_volume_change(int k) const { return worst_volume_[static_cast<std::size_t>(k)]; }
  /// Deepest node inside the pillar or a wall so far [um], 0 if none ever was.
  double worst_penetration_um(int k) const {
    return worst_depth_[static_cast<std::size_t>(k)] * dx_um_;
  }

 private:
  DldCell box_;
  double dx_um_;
  GuardLimits limits_;
  std::vector<double> v0_, worst_volume_, worst_depth_;
};

}  // namespace dld::membrane
