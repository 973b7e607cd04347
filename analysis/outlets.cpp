// SPDX-License-Identifier: MIT
#include "analysis/outlets.hpp"

#include <cmath>

namespace dld::analysis {

double inlet_band_bottom(const std::vector<double>& start_y_um, double lambda_um) {
  double mean = 0;
  for (double y : start_y_um) {
    mean += y;
  }
  if (!start_y_um.empty()) {
    mean /= static_cast<double>(start_y_um.size());
  }
  return lambda_um * std::floor(mean / lambda_um);
}

OutletBins outlet_bins(double y_in_um, double lambda_um, double d_um, int n_columns) {
  OutletBins b;
  b.y_in = y_in_um;
  const double lo = y_in_um - 2 * lambda_um;
  const double width = (n_columns * d_um + 3 * lambda_um) / 4;  // total N d + 3 lambda
  for (std::size_t i = 0; i < b.edges.size(); ++i) {
    b.edges[i] = lo + static_cast<double>(i) * width;
  }
  return b;
}

int outlet_of(const OutletBins& bins, double y_um) {
  if (y_um < bins.edges.front()) {
    return 0;
  }
  if (y_um > bins.edges.back()) {
    return 5;
  }
  for (int i = 1; i < 4; ++i) {
    if (y_um < bins.edges[static_cast<std::size_t>(i)]) {
      return i;
    }
  }
  return 4;  // the top edge belongs to O4
}

OutletCounts count_outlets(const OutletBins& bins, const std::vector<double>& end_y_um) {
  OutletCounts c;
  for (double y : end_y_um) {
    ++c.count[static_cast<std::size_t>(outlet_of(bins, y))];
  }
  c.total = static_cast<int>(end_y_um.size());
  return c;
}

}  // namespace dld::analysis
