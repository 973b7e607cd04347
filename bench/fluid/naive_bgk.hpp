// SPDX-License-Identifier: MIT
// The baseline: a plain two-array D3Q19 BGK loop on a fully periodic box, written the obvious
// way (array of structures, modulo indexing, push streaming, no forcing). Kept to measure the
// production kernel against, in the same run.
#pragma once
#include <vector>

namespace dld::bench {

class NaiveBgk {
 public:
  NaiveBgk(int nx, int ny, int nz, double tau);
  void step();
  double mass() const;
  long nodes() const { return static_cast<long>(nx_) * ny_ * nz_; }

 private:
  int nx_, ny_, nz_;
  double omega_;
  std::vector<double> f_, g_;  // f[node * 19 + i]
};

}  // namespace dld::bench
