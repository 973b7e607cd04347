// SPDX-License-Identifier: MIT
// Limited-memory BFGS (Nocedal & Wright, Numerical Optimization, 2nd ed., algorithm 7.4) with a
// backtracking Armijo line search: the quasi-static solver of membrane-only scenes.
#pragma once
#include <Eigen/Core>
#include <functional>

namespace dld::membrane {

struct LbfgsOptions {
  int max_iterations = 20000;
  int memory = 12;
  double gradient_tolerance = 1e-8;  ///< stop when max |dE/dx_i| falls below this
  double max_step = 0.1;             ///< largest move of any coordinate per iteration
};

struct LbfgsResult {
  int iterations = 0;
  double energy = 0.0;
  double max_gradient = 0.0;
  bool converged = false;
};

/// Energy and gradient at x: returns E, writes dE/dx into grad.
using Objective = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& grad)>;

LbfgsResult minimize_lbfgs(Eigen::VectorXd& x, const Objective& objective,
                           const LbfgsOptions& options);

}  // namespace dld::membrane
