// SPDX-License-Identifier: MIT
#include "memory_bandwidth.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

namespace dld::bench {

double measured_bandwidth_gb_s() {
  // 3 x 64 M doubles = 1.5 GB: well beyond the 105 MB L3 of this machine.
  const std::size_t n = std::size_t{1} << 26;
  std::vector<double> a(n), b(n, 1.0), c(n, 2.0);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) a[i] = 0.0;  // first touch by the same threads
  double best = 0;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 0.5 * c[i];
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::max(best, 4.0 * 8.0 * static_cast<double>(n) / s / 1e9);  // b, c, a (+ allocate)
  }
  volatile double sink = a[n / 2];
  (void)sink;
  return best;
}

}  // namespace dld::bench
