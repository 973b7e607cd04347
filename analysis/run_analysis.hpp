// SPDX-License-Identifier: MIT
// Everything dld-analyze reports about one run: per-cell results at N pillars, the failure
// probability's mean and standard deviation over the cells, and the outlet counts (SPEC section 7).
#pragma once
#include <string>
#include <vector>

#include "analysis/evaluation.hpp"
#include "analysis/expected_mode.hpp"
#include "analysis/outlets.hpp"
#include "analysis/run_file.hpp"

namespace dld::analysis {

struct RunAnalysis {
  int pillars_requested = 0;
  ExpectedMode expected;
  std::vector<CellResult> cells;   ///< every cell; pillars == 0 for those not evaluated
  std::vector<std::string> notes;  ///< cells evaluated short of N or not at all, one line each
  Stats p_f;                       ///< over the evaluated cells, when the expected mode is known
  int outlet_pillars = 0;          ///< the outlets are taken after this many columns (common N)
  OutletBins bins;
  OutletCounts outlets;
  std::vector<int> outlet_of_cell;  ///< per cell (as in `cells`): 0..5, -1 when not evaluated
  // How far the run got (SPEC 7 asks for them per run, beside the results):
  double last_step = 0;        ///< the last sample's time step
  double slowest_advance = 0;  ///< columns passed by the cell that passed fewest
  double volume_change = 0;    ///< largest |V / V(first sample) - 1| of any cell at any sample
};

/// Evaluates every cell at N = `pillars` columns (or the largest whole number it passed). The
/// outlets need one N for all cells: the smallest evaluated one. InputError if no cell passed a
/// whole column.
RunAnalysis analyze_run(const Run& run, int pillars, const ExpectedMode& expected);

}  // namespace dld::analysis
