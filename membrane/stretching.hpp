// SPDX-License-Identifier: MIT
// Optical-tweezers stretching of one cell, solved quasi-statically (no fluid): the total force F
// pulls on the nodes at each end of the major axis (x), split equally, and the membrane energy
// minus the work of the loads is minimised with L-BFGS (set-up of Mills et al., Mech. Chem.
// Biosyst. 1 (2004) 169, as used by Krueger's and Fedosov's validations).
#pragma once
#include <vector>

#include "membrane/lbfgs.hpp"
#include "membrane/model_registry.hpp"

namespace dld::membrane {

struct StretchOptions {
  double pulled_fraction = 0.05;  ///< fraction of all nodes pulled at each end [-]
  LbfgsOptions solver;
};

struct StretchPoint {
  double force = 0.0;          ///< total force on each end [lattice force]
  double axial = 0.0;          ///< D_A: extent along the pull [lattice lengths]
  double transverse = 0.0;     ///< D_T: largest extent across the pull [lattice lengths]
  double volume_change = 0.0;  ///< V/V0 - 1 [-]
  int iterations = 0;
  bool converged = false;
};

/// Solves one equilibrium per force, each starting from the previous one. `reference` is the rest
/// shape (axis z); the pull is along x.
std::vector<StretchPoint> stretch_cell(const TriMesh& reference, const MembraneMechanics& mechanics,
                                       const std::vector<double>& forces,
                                       const StretchOptions& options);

/// Largest extent of the nodes along x, and the largest extent across x (over directions in the
/// y-z plane, 1 degree apart).
double axial_diameter(const Points& x);
double transverse_diameter(const Points& x);

}  // namespace dld::membrane
