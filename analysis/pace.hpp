// SPDX-License-Identifier: MIT
// How far each cell of a run has got and how fast it goes: a run ends when every cell has passed N
// pillars (SPEC section 6), so its slowest cell, not the fluid's mean velocity, sets how long it
// takes. Used while a run goes (dld-analyze --pace) and to project what the study costs.
#pragma once
#include <string>
#include <vector>

#include "analysis/run_file.hpp"

namespace dld::analysis {

struct CellPace {
  int id = 0;
  double pillars = 0;           ///< columns passed so far: (x(last) - x(first)) / lambda
  double steps_per_pillar = 0;  ///< over the whole run so far; +inf when the cell has not advanced
  /// The first sample step from which on x stayed within lambda / 4 of its last value: a cell
  /// held (at a pillar, say) since then, if that is long ago; its pace so far is then no forecast.
  double still_since = 0;
  double x_um = 0, y_um = 0;  ///< its last centroid (device frame)
};

struct RunPace {
  double first_step = 0, last_step = 0;  ///< the samples the pace is taken between
  std::vector<CellPace> cells;           ///< ordered as the run's cells
  double mean_pillars = 0, median_pillars = 0;
  /// The time steps one column costs for the mean cell: elapsed steps / mean_pillars.
  double mean_steps_per_pillar() const;
  /// The time step at which every cell will have passed n pillars if each keeps its pace so far
  /// (+inf when a cell short of n has not advanced); `slowest` is set to that last cell's id.
  double step_every_cell_at(double n, int* slowest = nullptr) const;
  /// Cells whose x has stayed within lambda / 4 for more than `factor` times the mean cell's steps
  /// per pillar (a cell that long without advancing is held somewhere, not slow).
  std::vector<CellPace> held_cells(double factor = 2.0) const;
};

/// The pace of every cell between the run's first and last sample. InputError when the run has
/// fewer than two samples.
RunPace run_pace(const Run& run);

/// The terminal table of dld-analyze --pace: one line per cell, the mean and median, the
/// projected step at which the stop rule (every cell at n pillars) is met, and a line for each
/// held cell.
std::string format_pace(const Run& run, const RunPace& p, int n);

/// The per-cell CSV (cell, pillars, steps_per_pillar, step_at_n, still_since); returns its path.
std::string write_pace_csv(const RunPace& p, int n, const std::string& dir,
                           const std::string& base);

}  // namespace dld::analysis
