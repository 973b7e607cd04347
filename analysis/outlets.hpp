// SPDX-License-Identifier: MIT
// The four outlets after N columns (SPEC section 7): O1 (lowest) .. O4 split the lateral range
// [y_in - 2 lambda, y_in + N d + lambda] into equal bins, where [y_in, y_in + lambda] is the inlet
// band, the lambda-wide band of the box in which the cells start. An ideally displaced cell ends in
// the top lambda of O4; zigzag cells belong in O1 and O2, displaced ones in O3 and O4.
#pragma once
#include <array>
#include <vector>

namespace dld::analysis {

struct OutletBins {
  double y_in = 0;                ///< bottom of the inlet band [um]
  std::array<double, 5> edges{};  ///< O1 = [edges[0], edges[1]), ..., O4 = [edges[3], edges[4]]
};

/// y_in: the inlet band [y_in, y_in + lambda] holds the mean start y of the cells [um].
double inlet_band_bottom(const std::vector<double>& start_y_um, double lambda_um);

OutletBins outlet_bins(double y_in_um, double lambda_um, double d_um, int n_columns);

/// 1..4 for O1..O4; 0 below O1, 5 above O4 (outside the outlets).
int outlet_of(const OutletBins& bins, double y_um);

struct OutletCounts {
  std::array<int, 6> count{};  ///< [0] below O1, [1..4] O1..O4, [5] above O4
  int total = 0;
  /// count / total (0 when there are no cells).
  double fraction(int outlet) const {
    return total > 0 ? static_cast<double>(count[static_cast<std::size_t>(outlet)]) / total : 0.0;
  }
};

OutletCounts count_outlets(const OutletBins& bins, const std::vector<double>& end_y_um);

}  // namespace dld::analysis
