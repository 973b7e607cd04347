// SPDX-License-Identifier: MIT
// Per-cell results of a run (SPEC section 7): each cell is evaluated where its device x has
// advanced N lambda from its own start (linear between samples), against the expected mode:
//   zigzag:       p_fZ = (y(N) - y0) / (N lambda)
//   displacement: p_fD = -(y(N) - (y0 + N d)) / (N lambda), ceiling d / lambda (horizontal motion)
// Columns passed, shift per column and the observed mode come from shared/column_tracker (the
// rule the membrane program uses during the run).
#pragma once
#include <optional>
#include <vector>

#include "analysis/run_file.hpp"
#include "shared/column_tracker.hpp"

namespace dld::analysis {

/// y [um] where the cell's x first reaches x0 + advance_um (x0 = its first sample), linear between
/// the two samples around it; nullopt if it never gets there.
std::optional<double> y_at_advance(const CellTrack& cell, double advance_um);

/// Columns (lambda) the cell's x advanced at most from its start, fractional.
double max_advance_columns(const CellTrack& cell, double lambda_um);

/// SPEC section 7; n pillars >= 1, lengths in um.
double zigzag_failure(double y0, double y_end, int n, double lambda_um);
double displacement_failure(double y0, double y_end, int n, double lambda_um, double d_um);
/// The failure probability for an expected mode (kZigzag or kDisplacement); nullopt otherwise.
std::optional<double> failure_probability(TransportMode expected, double y0, double y_end, int n,
                                          double lambda_um, double d_um);

struct CellResult {
  int id = 0;
  double x0 = 0, y0 = 0;        ///< start [um]
  double advance = 0;           ///< largest advance from the start [columns, fractional]
  int columns = 0;              ///< whole columns passed
  int pillars = 0;              ///< evaluated at min(N, columns); 0: not evaluated
  double y_end = 0;             ///< y at x0 + pillars lambda [um]
  double shift_per_column = 0;  ///< [um], NaN before two columns
  TransportMode mode = TransportMode::kUndecided;  ///< observed (final_mode of the tracker)
  std::optional<double> p_f;                       ///< for the expected mode, when it is known
};

CellResult evaluate_cell(const CellTrack& cell, double lambda_um, double d_um, int pillars,
                         TransportMode expected);

struct Stats {
  double mean = 0, std = 0;  ///< std: sample standard deviation (n - 1), NaN for n < 2
  int n = 0;
};
Stats mean_std(const std::vector<double>& v);

}  // namespace dld::analysis
