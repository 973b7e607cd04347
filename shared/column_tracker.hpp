// SPDX-License-Identifier: MIT
// Columns passed and the transport mode of each cell during a coupled run (SPEC section 7), from
// the cells' centroids in device coordinates [um]. It drives the run's progress output and its
// stop rules (a pillar target; stopping once every cell's mode is certain).
//
// Mode rule (dilute-limit runs, issue 4): y is taken where the cell crosses whole columns
// (x = x0 + c lambda, interpolated between samples, so the phase within a column does not bias it);
// after the first column (entry transient) the mean lateral shift per column
// s = (y(c) - y(1)) / (c - 1) is ~d for displacement and ~0 for zigzag (a zigzag cell follows the
// flow and keeps its device y). The mode is the nearer of the two; it is "certain" once the cell
// has passed one whole zigzag period, ceil(lambda/d) + 1 columns and at least 5, with s within d/5
// of it. A cell that never gets there (s stays in between) is reported "mixed" when the run ends.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

namespace dld {

enum class TransportMode { kUndecided, kZigzag, kDisplacement, kMixed };
std::string to_string(TransportMode m);

class ColumnTracker {
 public:
  /// lambda and d in um; starts = the cells' initial centroids [um, device frame].
  ColumnTracker(double lambda_um, double row_shift_um, std::vector<Eigen::Vector3d> starts);

  /// Records the centroids at a sample (same order as the starts).
  void update(const std::vector<Eigen::Vector3d>& centroids);

  int cells() const { return static_cast<int>(start_.size()); }
  /// Whole columns cell k has passed since its start: floor((x - x0) / lambda).
  int columns(int k) const;
  double fractional_columns(int k) const;
  int min_columns() const;
  /// Mean lateral shift per column after the first column [um]; NaN before two columns.
  double shift_per_column(int k) const;
  /// The nearer mode once enough columns are passed (kUndecided before).
  TransportMode mode(int k) const;
  bool certain(int k) const;
  /// mode() if certain, kMixed if not (for the end of a run).
  TransportMode final_mode(int k) const;
  /// Columns after which a mode can be certain (one zigzag period, at least 5).
  int columns_for_certainty() const;
  bool all_modes_certain() const;

 private:
  double lambda_, d_;
  std::vector<Eigen::Vector3d> start_, now_;
  std::vector<std::vector<double>> crossing_y_;  ///< device y at columns 1, 2, ... of each cell
};

}  // namespace dld
