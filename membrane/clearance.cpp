// SPDX-License-Identifier: MIT
#include "membrane/clearance.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace dld::membrane {
namespace {

struct Box3 {
  Eigen::Vector3d lo, hi;
  bool near(const Eigen::Vector3d& p, double pad) const {
    return (p.array() >= lo.array() - pad).all() && (p.array() <= hi.array() + pad).all();
  }
  bool overlaps(const Box3& o, double pad) const {
    return (lo.array() - pad <= o.hi.array()).all() && (o.lo.array() <= hi.array() + pad).all();
  }
};

}  // namespace

Clearances clearances(const Points& x, int n, const DldCell& box, double cap) {
  const int cells = static_cast<int>(x.cols()) / n;
  Clearances c{cap, 1e300, 1e300};
  for (int i = 0; i < x.cols(); ++i) {
    c.walls = std::min({c.walls, x(2, i), box.depth - x(2, i)});
    c.pillar = std::min(c.pillar, box.pillar_distance(x(0, i), x(1, i)));
  }
  std::vector<Box3> bounds(cells);
  for (int k = 0; k < cells; ++k) {
    const auto xk = x.middleCols(Eigen::Index{k} * n, n);
    bounds[k] = {xk.rowwise().minCoeff(), xk.rowwise().maxCoeff()};
  }
  // Images of cell l: shifted periodic x (one column either way moves y by +-d), periodic y.
  // Two y periods either way cover every pair of cells whose centroids lie in the box.
  for (int k = 0; k < cells; ++k)
    for (int l = k + 1; l < cells; ++l)
      for (int ix = -1; ix <= 1; ++ix)
        for (int iy = -2; iy <= 2; ++iy) {
          const Eigen::Vector3d t(ix * box.lambda, ix * box.shift + iy * box.lambda, 0.0);
          const Box3 bl{bounds[l].lo + t, bounds[l].hi + t};
          if (!bounds[k].overlaps(bl, c.cells)) continue;
          // Nodes of each cell near the other's bounds, then all pairs of those.
          std::vector<int> ak, al;
          for (int i = 0; i < n; ++i) {
            if (bl.near(x.col(k * n + i), c.cells)) ak.push_back(k * n + i);
            if (bounds[k].near(x.col(l * n + i) + t, c.cells)) al.push_back(l * n + i);
          }
          for (int i : ak)
            for (int j : al) c.cells = std::min(c.cells, (x.col(i) - x.col(j) - t).norm());
        }
  return c;
}

int nodes_inside_other_cells(const Points& x, const std::vector<Face>& faces, int n,
                             const DldCell& box) {
  const int cells = static_cast<int>(x.cols()) / n;
  std::vector<Box3> bounds(cells);
  for (int k = 0; k < cells; ++k) {
    const auto xk = x.middleCols(Eigen::Index{k} * n, n);
    bounds[k] = {xk.rowwise().minCoeff(), xk.rowwise().maxCoeff()};
  }
  // Solid angle of every face of cell l seen from p (Van Oosterom & Strackee 1983), summed: 4 pi
  // inside a closed outward surface, 0 outside.
  auto winding = [&](const Eigen::Vector3d& p, int l, const Eigen::Vector3d& t) {
    double w = 0.0;
    for (const Face& f : faces) {
      const Eigen::Vector3d a = x.col(l * n + f[0]) + t - p, b = x.col(l * n + f[1]) + t - p,
                            c = x.col(l * n + f[2]) + t - p;
      const double la = a.norm(), lb = b.norm(), lc = c.norm();
      w += 2.0 * std::atan2(a.dot(b.cross(c)),
                            la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
    }
    return w / (4.0 * M_PI);
  };
  int inside = 0;
  for (int k = 0; k < cells; ++k)
    for (int l = 0; l < cells; ++l) {
      if (l == k) continue;
      for (int ix = -1; ix <= 1; ++ix)
        for (int iy = -2; iy <= 2; ++iy) {
          const Eigen::Vector3d t(ix * box.lambda, ix * box.shift + iy * box.lambda, 0.0);
          const Box3 bl{bounds[l].lo + t, bounds[l].hi + t};
          if (!bounds[k].overlaps(bl, 0.0)) continue;
          for (int i = 0; i < n; ++i)
            if (bl.near(x.col(k * n + i), 0.0) && winding(x.col(k * n + i), l, t) > 0.5) ++inside;
        }
    }
  return inside;
}

void fold_cells_into_box(Points& x, int n, const DldCell& box) {
  for (int k = 0; Eigen::Index{k} * n < x.cols(); ++k) {
    auto xk = x.middleCols(Eigen::Index{k} * n, n);
    const Eigen::Vector3d c = xk.rowwise().mean();
    const Wrapped w = wrap_into_box(box, {c.x(), c.y(), c.z()});
    const Eigen::Vector3d shift(w.position[0] - c.x(), w.position[1] - c.y(), 0.0);
    xk.colwise() += shift;
  }
}

}  // namespace dld::membrane
