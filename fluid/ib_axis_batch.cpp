// SPDX-License-Identifier: MIT
// Built with -fno-math-errno and -fno-trapping-math (fluid/CMakeLists.txt) so that GCC vectorises
// the floors and square roots; neither changes a result (no errno, no FP traps are read), and the
// radicands are never negative (1 + 4 s - 4 s^2 >= 1 for s in [0, 1)).
#include "fluid/ib_axis_batch.hpp"

#include <cmath>

namespace dld::fluid {

namespace {
// axis_weights<4>(kPeskin4, c, w) for lane l; `first` kept as a double (an exact integer).
inline void axis(double c, double (&w)[4][kIbBatch], double* first, int l) {
  const double f = std::floor(c - 0.5 - 0.5 * 4) + 1;
  const double s = c - 0.5 - (f + 1);
  const double q = std::sqrt(1.0 + 4.0 * s - 4.0 * s * s);
  w[0][l] = (3.0 - 2.0 * s - q) * 0.125;
  w[1][l] = (3.0 - 2.0 * s + q) * 0.125;
  w[2][l] = (1.0 + 2.0 * s + q) * 0.125;
  w[3][l] = (1.0 + 2.0 * s - q) * 0.125;
  first[l] = f;
}
}  // namespace

void peskin4_axis_batch(const double* positions, const std::uint32_t* index, int n, double nx,
                        double ny, double shift, Peskin4AxisBatch& out) {
  // The markers' coordinates side by side first: GCC 12 does not vectorise the indexed loads.
  double x[kIbBatch], y[kIbBatch], z[kIbBatch];
  for (int l = 0; l < n; ++l) {
    const double* p = positions + 3 * static_cast<std::size_t>(index[l]);
    x[l] = p[0], y[l] = p[1], z[l] = p[2];
  }
  for (int l = n; l < kIbBatch; ++l) x[l] = y[l] = z[l] = 0.5 * nx;  // unused lanes
#pragma omp simd
  for (int l = 0; l < kIbBatch; ++l) {
    const double wraps = std::floor(x[l] / nx);
    axis(x[l] - wraps * nx, out.w[0], out.first[0], l);
    axis(y[l] - wraps * shift, out.w[1], out.first[1], l);
    axis(z[l], out.w[2], out.first[2], l);
    // The first y row wrapped into [0, ny) (exact: whole numbers far below 2^53); done marker by
    // marker as ((j % ny) + ny) % ny, its two integer divisions were a tenth of the footprints'
    // time, since a marker's y is not folded into the box.
    const double j = out.first[1][l];
    double row = j - std::floor(j / ny) * ny;
    row = row < 0.0 ? row + ny : row;
    out.first[1][l] = row >= ny ? row - ny : row;
  }
}

}  // namespace dld::fluid
