// SPDX-License-Identifier: MIT
#include "membrane/lbfgs.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace dld::membrane {

LbfgsResult minimize_lbfgs(Eigen::VectorXd& x, const Objective& objective, const LbfgsOptions& o) {
  LbfgsResult r;
  Eigen::VectorXd g(x.size()), g_new(x.size()), x_new(x.size());
  double e = objective(x, g);
  std::deque<Eigen::VectorXd> s_hist, y_hist;
  std::deque<double> rho_hist;
  for (r.iterations = 0; r.iterations < o.max_iterations; ++r.iterations) {
    r.max_gradient = g.cwiseAbs().maxCoeff();
    if (r.max_gradient < o.gradient_tolerance) {
      r.converged = true;
      break;
    }
    // Two-loop recursion for d = -H g.
    Eigen::VectorXd q = g;
    std::vector<double> alpha(s_hist.size());
    for (int i = static_cast<int>(s_hist.size()) - 1; i >= 0; --i) {
      alpha[i] = rho_hist[i] * s_hist[i].dot(q);
      q -= alpha[i] * y_hist[i];
    }
    if (!s_hist.empty()) q *= s_hist.back().dot(y_hist.back()) / y_hist.back().squaredNorm();
    for (std::size_t i = 0; i < s_hist.size(); ++i) {
      const double beta = rho_hist[i] * y_hist[i].dot(q);
      q += s_hist[i] * (alpha[i] - beta);
    }
    Eigen::VectorXd d = -q;
    if (d.dot(g) >= 0.0) {  // not a descent direction: restart from steepest descent
      d = -g;
      s_hist.clear(), y_hist.clear(), rho_hist.clear();
    }
    double step = std::min(1.0, o.max_step / d.cwiseAbs().maxCoeff());
    double e_new = 0.0;
    bool accepted = false;
    for (int ls = 0; ls < 60; ++ls) {
      x_new = x + step * d;
      e_new = objective(x_new, g_new);
      if (std::isfinite(e_new) && e_new <= e + 1e-4 * step * d.dot(g)) {
        accepted = true;
        break;
      }
      step *= 0.5;
    }
    if (!accepted) break;  // no progress possible at round-off level
    Eigen::VectorXd s = x_new - x, y = g_new - g;
    const double sy = s.dot(y);
    if (sy > 1e-16 * s.norm() * y.norm()) {
      s_hist.push_back(std::move(s));
      y_hist.push_back(std::move(y));
      rho_hist.push_back(1.0 / sy);
      if (static_cast<int>(s_hist.size()) > o.memory) {
        s_hist.pop_front(), y_hist.pop_front(), rho_hist.pop_front();
      }
    }
    x.swap(x_new);
    g.swap(g_new);
    e = e_new;
  }
  r.energy = e;
  r.max_gradient = g.cwiseAbs().maxCoeff();
  r.converged = r.converged || r.max_gradient < o.gradient_tolerance;
  return r;
}

}  // namespace dld::membrane
