// SPDX-License-Identifier: MIT
#include "analysis/run_analysis.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::analysis {

namespace {

/// last_step, slowest_advance and volume_change of `a` from the tracks and the evaluated cells.
void add_run_extent(const Run& run, RunAnalysis& a) {
  a.slowest_advance = a.cells.empty() ? 0 : a.cells.front().advance;
  for (const CellResult& r : a.cells) a.slowest_advance = std::min(a.slowest_advance, r.advance);
  for (const CellTrack& t : run.cells) {
    if (!t.step.empty()) a.last_step = std::max(a.last_step, t.step.back());
    if (t.volume.empty() || !(t.volume.front() > 0)) continue;
    for (const double v : t.volume)
      a.volume_change = std::max(a.volume_change, std::abs(v / t.volume.front() - 1));
  }
}

}  // namespace

RunAnalysis analyze_run(const Run& run, int pillars, const ExpectedMode& expected) {
  RunAnalysis a;
  a.pillars_requested = pillars;
  a.expected = expected;
  std::vector<double> p_f, start_y;
  double most = 0;
  a.outlet_pillars = pillars;
  for (const CellTrack& t : run.cells) {
    const CellResult r = evaluate_cell(t, run.lambda_um, run.row_shift_um, pillars, expected.mode);
    most = std::max(most, r.advance);
    if (r.pillars < 1) {
      a.notes.push_back(fmt::format(
          "cell {}: advanced {:.2f} columns, less than one: not evaluated", r.id, r.advance));
    } else {
      if (r.pillars < pillars) {
        a.notes.push_back(
            fmt::format("cell {}: advanced {:.2f} columns, fewer than {}: evaluated at {} pillars",
                        r.id, r.advance, pillars, r.pillars));
      }
      if (r.p_f) {
        p_f.push_back(*r.p_f);
      }
      start_y.push_back(r.y0);
      a.outlet_pillars = std::min(a.outlet_pillars, r.pillars);
    }
    a.cells.push_back(r);
  }
  if (start_y.empty()) {
    throw InputError(fmt::format(
        "{}: no cell advanced a whole pillar (at most {:.2f} columns): nothing to evaluate",
        run.files.front(), most));
  }
  a.p_f = mean_std(p_f);

  // Outlets after the common number of columns (SPEC section 7).
  a.bins = outlet_bins(inlet_band_bottom(start_y, run.lambda_um), run.lambda_um, run.row_shift_um,
                       a.outlet_pillars);
  std::vector<double> end_y;
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    const CellResult& r = a.cells[k];
    if (r.pillars < 1) {
      a.outlet_of_cell.push_back(-1);
      continue;
    }
    // Every evaluated cell passed outlet_pillars columns, so the position exists.
    end_y.push_back(*y_at_advance(run.cells[k], a.outlet_pillars * run.lambda_um));
    a.outlet_of_cell.push_back(outlet_of(a.bins, end_y.back()));
  }
  a.outlets = count_outlets(a.bins, end_y);
  add_run_extent(run, a);
  if (a.outlet_pillars < pillars) {
    a.notes.push_back(
        fmt::format("outlets taken after {} columns (the fewest any cell passed), not {}",
                    a.outlet_pillars, pillars));
  }
  return a;
}

}  // namespace dld::analysis
