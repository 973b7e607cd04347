// SPDX-License-Identifier: MIT
// Watches each cell's smallest triangle area ratio J = A/A_rest over a run. Skalak's area term
// resists compression less and less below J = 1/sqrt(3) and not at all as J -> 0; in the dense
// runs triangles in the film against the pillar and the walls collapsed there before the run went
// unstable (docs/results-history.md, "Why the dense runs go unstable late"), so a cell passing
// below it is worth a warning, and the progress lines and the summary show the smallest J. Reads
// positions only: the physics is unchanged.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "membrane/cell_set.hpp"

namespace dld::membrane {

class TriangleWatch {
 public:
  /// Where Skalak's area tension J (1 - J^2) peaks.
  static constexpr double kSkalakPeak = 0.57735026918962576;

  explicit TriangleWatch(const TriMesh& reference);

  /// Takes each cell's smallest J now; returns one warning line per cell that went below
  /// kSkalakPeak for the first time in this process (cells named by global index first_cell + k).
  std::vector<std::string> update(const CellSet& cells, std::int64_t step, int first_cell);

  /// Cell k's smallest J at the last update, and over every update so far (1 before any).
  double now(int k) const { return at(now_, k); }
  double smallest(int k) const { return at(smallest_, k); }
  /// The local index of the cell with the smallest J at the last update (-1 before any).
  int worst_cell_now() const;

 private:
  // A run shorter than one sample ends with its summary before any update.
  static double at(const std::vector<double>& v, int k) {
    const auto i = static_cast<std::size_t>(k);
    return i < v.size() ? v[i] : 1.0;
  }
  std::vector<Face> faces_;
  std::vector<double> rest_area_;
  std::vector<double> now_, smallest_;
  std::vector<bool> warned_;
};

}  // namespace dld::membrane
