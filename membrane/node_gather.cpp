// SPDX-License-Identifier: MIT
#include "membrane/node_gather.hpp"

namespace dld::membrane {

NodeGather::NodeGather(const std::vector<int>& corners, int node_count)
    : start_(node_count + 1, 0) {
  for (int n : corners) start_[n + 1]++;
  for (int i = 0; i < node_count; ++i) start_[i + 1] += start_[i];
  slots_.resize(corners.size());
  std::vector<int> fill(start_.begin(), start_.end() - 1);
  for (int s = 0; s < static_cast<int>(corners.size()); ++s) slots_[fill[corners[s]]++] = s;
}

void NodeGather::add(const Eigen::Matrix3Xd& slot_forces, Eigen::Ref<Eigen::Matrix3Xd> f) const {
  const int n = static_cast<int>(start_.size()) - 1;
#pragma omp parallel for schedule(static) if (n > 8192)
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int s = start_[i]; s < start_[i + 1]; ++s) sum += slot_forces.col(slots_[s]);
    f.col(i) += sum;
  }
}

}  // namespace dld::membrane
