// SPDX-License-Identifier: MIT
// Race-free parallel force assembly: elements write their corner forces to their own slots, then
// every node sums its slots (node -> slot lists in CSR form). Used by the per-element models.
#pragma once
#include <Eigen/Core>
#include <vector>

namespace dld::membrane {

class NodeGather {
 public:
  NodeGather() = default;
  /// `corners[e * k + j]` is node j of element e (k corners per element).
  NodeGather(const std::vector<int>& corners, int node_count);
  /// f.col(i) += sum of slot_forces.col(s) over the slots s of node i.
  void add(const Eigen::Matrix3Xd& slot_forces, Eigen::Ref<Eigen::Matrix3Xd> f) const;

 private:
  std::vector<int> start_;  ///< node i owns slots_[start_[i] .. start_[i+1])
  std::vector<int> slots_;
};

}  // namespace dld::membrane
