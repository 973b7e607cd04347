// SPDX-License-Identifier: MIT
#include "membrane/triangle_watch.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <limits>

namespace dld::membrane {
namespace {
double triangle_area(const Eigen::Ref<const Points>& x, const Face& t) {
  return 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
}
}  // namespace

TriangleWatch::TriangleWatch(const TriMesh& reference) : faces_(reference.faces) {
  rest_area_.reserve(faces_.size());
  for (const Face& t : faces_) rest_area_.push_back(triangle_area(reference.nodes, t));
}

std::vector<std::string> TriangleWatch::update(const CellSet& cells, std::int64_t step,
                                               int first_cell) {
  const auto n = static_cast<std::size_t>(cells.cell_count());
  now_.resize(n, 1.0);
  smallest_.resize(n, 1.0);
  warned_.resize(n, false);
  std::vector<std::string> warnings;
  for (std::size_t k = 0; k < n; ++k) {
    const auto x = cells.cell_positions(static_cast<int>(k));
    double least = std::numeric_limits<double>::infinity();
    std::size_t worst = 0;
    for (std::size_t i = 0; i < faces_.size(); ++i) {
      const double j = triangle_area(x, faces_[i]) / rest_area_[i];
      if (j < least) least = j, worst = i;
    }
    now_[k] = least;
    smallest_[k] = std::min(smallest_[k], least);
    if (least < kSkalakPeak && !warned_[k]) {
      warned_[k] = true;
      warnings.push_back(fmt::format(
          "cell {} triangle {} is compressed to {:.2f} of its rest area at step {}: below "
          "1/sqrt(3), where Skalak's area term gives way (collapsed triangles, in the film against "
          "the pillar or a wall, came before the dense runs' late stops: docs/results-history.md)",
          first_cell + static_cast<int>(k), worst, least, step));
    }
  }
  return warnings;
}

int TriangleWatch::worst_cell_now() const {
  if (now_.empty()) return -1;
  return static_cast<int>(std::min_element(now_.begin(), now_.end()) - now_.begin());
}

}  // namespace dld::membrane
