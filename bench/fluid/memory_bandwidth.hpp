// SPDX-License-Identifier: MIT
#pragma once

namespace dld::bench {
/// Measured main-memory bandwidth [GB/s] of this machine for a copy-like kernel
/// (a[i] = b[i] + s c[i]: two streams read, one written) over arrays far larger than the caches,
/// with the current number of OpenMP threads. Counts write-allocate traffic as a read.
double measured_bandwidth_gb_s();
}  // namespace dld::bench
