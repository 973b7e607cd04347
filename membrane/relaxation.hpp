// SPDX-License-Identifier: MIT
// Overdamped relaxation of cells without fluid: dX/dt = mobility * F(X), explicit Euler with a
// step that halves whenever the energy would rise (so it cannot blow up) and grows slowly back.
#pragma once
#include <functional>

#include "membrane/cell_set.hpp"

namespace dld::membrane {

struct RelaxOptions {
  double mobility = 1.0;   ///< node velocity per unit force [lattice velocity / lattice force]
  double time_step = 1.0;  ///< initial step [lattice time]
  int max_steps = 10000;
  double force_tolerance = 0.0;  ///< stop when the largest node force falls below this
};

struct RelaxResult {
  int steps = 0;
  double energy = 0.0;
  double max_force = 0.0;
  double time = 0.0;  ///< relaxation time elapsed [lattice time]
};

/// Called every `every` steps with the step number (for logging / time series); may be empty.
using RelaxObserver = std::function<void(int step, double energy, double max_force)>;

RelaxResult relax_overdamped(CellSet& cells, const RelaxOptions& options,
                             const RelaxObserver& observer = {}, int every = 100);

}  // namespace dld::membrane
