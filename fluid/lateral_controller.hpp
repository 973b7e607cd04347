// SPDX-License-Identifier: MIT
// Keeps the box-mean lateral velocity at zero (SPEC section 3: far-away side walls allow no net
// lateral flow) by adjusting a uniform y body force. Proportional-integral control on <u_y>,
// gains scaled by the box's estimated mobility <u>/F = H^2 / (12 nu) (plane Poiseuille) and its
// viscous response time H^2 / (pi^2 nu). Lattice units.
#pragma once

namespace dld::fluid {

class LateralController {
 public:
  /// depth_lu: channel depth H (or a box size if there are no walls); nu_lu: outer viscosity.
  LateralController(double depth_lu, double nu_lu);
  /// Returns the new y force density given the mean u_y of the last step.
  double update(double mean_uy);
  double force() const { return force_; }
  void set_force(double f) { force_ = integral_ = f; }
  /// The controller's memory, for checkpoints.
  double integral() const { return integral_; }
  void restore(double integral, double force) {
    integral_ = integral;
    force_ = force;
  }

 private:
  double mobility_;
  double gain_i_;  ///< integral gain per step
  double gain_p_;  ///< proportional gain
  double integral_ = 0.0;
  double force_ = 0.0;
};

}  // namespace dld::fluid
