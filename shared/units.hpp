// SPDX-License-Identifier: MIT
// The one place where physical (SI) values become lattice values and back.
// Lattice units: dx = dt = rho0 = 1. Names of lattice quantities end in _lu.
#pragma once

namespace dld {

/// Relaxation time of a fluid `ratio` times as viscous as one relaxing with `tau`:
/// nu = (tau - 1/2)/3, so tau_in = 1/2 + ratio (tau - 1/2) [-].
inline double inner_relaxation_time(double tau, double ratio) {
  return 0.5 + ratio * (tau - 0.5);
}

class LatticeUnits {
 public:
  /// dx_m: lattice spacing [m]; tau: outer relaxation time [-]; nu_m2_s: outer kinematic
  /// viscosity [m^2/s]; rho_kg_m3: fluid density [kg/m^3]. The time step follows from
  /// nu_lu = (tau - 1/2)/3 = nu dt / dx^2.
  LatticeUnits(double dx_m, double tau, double nu_m2_s, double rho_kg_m3);

  double dx_m() const { return dx_; }
  double dt_s() const { return dt_; }
  double rho_kg_m3() const { return rho_; }
  double nu_lu() const { return nu_lu_; }

  double length_lu(double metres) const { return metres / dx_; }
  double length_m(double lu) const { return lu * dx_; }
  double time_lu(double seconds) const { return seconds / dt_; }
  double time_s(double lu) const { return lu * dt_; }
  double velocity_lu(double m_s) const { return m_s * dt_ / dx_; }
  double velocity_m_s(double lu) const { return lu * dx_ / dt_; }
  /// Force per volume [N/m^3 = Pa/m]: mass unit rho dx^3, so f_lu = f dt^2 / (rho dx).
  double force_density_lu(double n_m3) const { return n_m3 * dt_ * dt_ / (rho_ * dx_); }
  double force_density_n_m3(double lu) const { return lu * rho_ * dx_ / (dt_ * dt_); }
  /// Force [N]: f_lu = f dt^2 / (rho dx^4).
  double force_lu(double newton) const {
    return newton * dt_ * dt_ / (rho_ * dx_ * dx_ * dx_ * dx_);
  }
  double force_n(double lu) const { return lu * rho_ * dx_ * dx_ * dx_ * dx_ / (dt_ * dt_); }
  /// Surface modulus or tension [N/m]: k_lu = k dt^2 / (rho dx^3).
  double modulus_lu(double n_m) const { return n_m * dt_ * dt_ / (rho_ * dx_ * dx_ * dx_); }
  double modulus_n_m(double lu) const { return lu * rho_ * dx_ * dx_ * dx_ / (dt_ * dt_); }
  /// Energy [J]: e_lu = e dt^2 / (rho dx^5).
  double energy_lu(double joule) const {
    return joule * dt_ * dt_ / (rho_ * dx_ * dx_ * dx_ * dx_ * dx_);
  }

 private:
  double dx_;
  double dt_;
  double rho_;
  double nu_lu_;
};

}  // namespace dld
