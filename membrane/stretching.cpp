// SPDX-License-Identifier: MIT
#include "membrane/stretching.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "shared/input_error.hpp"

namespace dld::membrane {

double axial_diameter(const Points& x) {
  return x.row(0).maxCoeff() - x.row(0).minCoeff();
}

double transverse_diameter(const Points& x) {
  double best = 0.0;
  for (int a = 0; a < 180; ++a) {
    const double t = a * M_PI / 180.0;
    const Eigen::RowVectorXd p = std::cos(t) * x.row(1) + std::sin(t) * x.row(2);
    best = std::max(best, p.maxCoeff() - p.minCoeff());
  }
  return best;
}

std::vector<StretchPoint> stretch_cell(const TriMesh& reference, const MembraneMechanics& mechanics,
                                       const std::vector<double>& forces, const StretchOptions& o) {
  const int n = reference.node_count();
  const int pulled = std::max(1, static_cast<int>(std::lround(o.pulled_fraction * n)));
  if (!(o.pulled_fraction > 0.0 && o.pulled_fraction < 0.5))
    throw InputError(
        fmt::format("stretch: pulled fraction must be in (0, 0.5), got {}", o.pulled_fraction));
  // The `pulled` nodes of largest x get +F/pulled each, those of smallest x -F/pulled.
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return reference.nodes(0, a) < reference.nodes(0, b); });
  Eigen::VectorXd load_dir = Eigen::VectorXd::Zero(3 * n);
  for (int k = 0; k < pulled; ++k) {
    load_dir(3 * order[k]) = -1.0 / pulled;
    load_dir(3 * order[n - 1 - k]) = 1.0 / pulled;
  }
  const double v0 = enclosed_volume(reference);
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(reference.nodes.data(), 3 * n);
  Points f(3, n);
  std::vector<StretchPoint> out;
  for (double force : forces) {
    const Eigen::VectorXd load = force * load_dir;
    auto objective = [&](const Eigen::VectorXd& xv, Eigen::VectorXd& grad) {
      Eigen::Map<const Points> xp(xv.data(), 3, n);
      f.setZero();
      const double e = mechanics.add_forces(xp, f);
      grad = -Eigen::Map<const Eigen::VectorXd>(f.data(), 3 * n) - load;
      return e - load.dot(xv);
    };
    const LbfgsResult r = minimize_lbfgs(x, objective, o.solver);
    Eigen::Map<const Points> xp(x.data(), 3, n);
    StretchPoint p;
    p.force = force;
    p.axial = axial_diameter(xp);
    p.transverse = transverse_diameter(xp);
    p.volume_change = enclosed_volume(reference, xp) / v0 - 1.0;
    p.iterations = r.iterations;
    p.converged = r.converged;
    spdlog::debug("stretch F {:.4g}: D_A {:.4g}, D_T {:.4g}, {} iterations, |g| {:.2g}", force,
                  p.axial, p.transverse, r.iterations, r.max_gradient);
    out.push_back(p);
  }
  return out;
}

}  // namespace dld::membrane
