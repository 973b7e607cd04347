// SPDX-License-Identifier: MIT
#include "membrane/relaxation.hpp"

#include <cmath>

namespace dld::membrane {

RelaxResult relax_overdamped(CellSet& cells, const RelaxOptions& o, const RelaxObserver& observer,
                             int every) {
  RelaxResult r;
  Points f;
  double e = cells.compute_forces(f);
  double dt = o.time_step;
  for (r.steps = 0; r.steps < o.max_steps; ++r.steps) {
    r.max_force = f.colwise().norm().maxCoeff();
    if (observer && r.steps % every == 0) observer(r.steps, e, r.max_force);
    if (r.max_force <= o.force_tolerance) break;
    const Points x_old = cells.positions();
    bool accepted = false;
    for (int tries = 0; tries < 50 && !accepted; ++tries) {
      cells.positions() = x_old + (dt * o.mobility) * f;
      Points f_new;
      const double e_new = cells.compute_forces(f_new);
      if (std::isfinite(e_new) && e_new <= e) {
        e = e_new;
        f.swap(f_new);
        r.time += dt;
        dt = std::min(o.time_step, dt * 1.1);
        accepted = true;
      } else {
        dt *= 0.5;
      }
    }
    if (!accepted) {  // stuck at round-off: keep the last good state
      cells.positions() = x_old;
      break;
    }
  }
  r.energy = e;
  r.max_force = f.colwise().norm().maxCoeff();
  return r;
}

}  // namespace dld::membrane
