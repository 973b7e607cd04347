// SPDX-License-Identifier: MIT
#pragma once
#include <cmath>

#include "fluid/fluid_solver.hpp"

namespace dld::fluid::testing {

/// Steps until the mean x velocity changes by less than `tol` (relative) over `every` steps.
inline void run_to_steady(FluidSolver& s, double tol, int every, long max_steps) {
  double last = 0;
  while (s.steps() < max_steps) {
    for (int i = 0; i < every; ++i) s.step();
    const double u = s.mean_velocity()[0];
    if (std::abs(u - last) <= tol * std::abs(u)) return;
    last = u;
  }
}

}  // namespace dld::fluid::testing
