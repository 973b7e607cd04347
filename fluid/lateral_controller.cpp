// SPDX-License-Identifier: MIT
#include "fluid/lateral_controller.hpp"

#include <cmath>

namespace dld::fluid {

LateralController::LateralController(double depth_lu, double nu_lu) {
  mobility_ = depth_lu * depth_lu / (12.0 * nu_lu);
  const double response_steps = depth_lu * depth_lu / (M_PI * M_PI * nu_lu);
  // Integral time of about one and a half response times keeps the loop well damped; the
  // proportional part cancels most of an error within one response time.
  gain_i_ = 1.0 / (1.5 * response_steps);
  gain_p_ = 0.5;
}

double LateralController::update(double mean_uy) {
  const double error_force = mean_uy / mobility_;  // force that would produce this u_y at rest
  integral_ -= gain_i_ * error_force;
  force_ = integral_ - gain_p_ * error_force;
  return force_;
}

}  // namespace dld::fluid
