// SPDX-License-Identifier: MIT
// An initially spherical capsule in simple shear (the capsule benchmark of Ramanujan & Pozrikidis,
// J. Fluid Mech. 361 (1998) 117): a box with walls at z = 0 and z = nz moving at -U and +U along x
// (moving-wall bounce-back), periodic x and y, the capsule of radius a in the middle. The fluid
// (lattice Boltzmann + immersed boundary) and the membrane (finite elements) run as two threads of
// this process and exchange nodes over the coupler, on a selectable transport.
// Everything here is in lattice units (dx = dt = rho0 = 1); the benchmark is dimensionless.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fluid/ib_kernel.hpp"
#include "membrane/mesh.hpp"
#include "shared/scene.hpp"

namespace dld::validation {

enum class Transport { inproc, ipc, tcp };
Transport transport_from_name(const std::string& name);  ///< "inproc", "ipc", "tcp"
std::string name(Transport t);

enum class MembraneLaw { neo_hookean, skalak };

struct CapsuleShearSetup {
  double radius = 6.0;            ///< a [lattice lengths]
  int nx = 48, ny = 48, nz = 48;  ///< box [nodes]; walls at z = 0 and z = nz
  int faces = 1280;               ///< icosphere faces (20 * 4^n, the nearest is used)
  double reynolds = 0.1;          ///< Re = gammadot a^2 / nu
  double tau = 1.0;               ///< relaxation time (TRT, Lambda = 3/16): nu = (tau - 1/2)/3
  /// Ca = mu gammadot a / E_s with E_s = 3 G_s: the convention of the reference data
  /// (Ramanujan & Pozrikidis 1998; tests/data/capsule_shear/README.md).
  double capillary = 0.1;
  MembraneLaw law = MembraneLaw::neo_hookean;
  double skalak_c = 1.0;         ///< C = kappa_alpha/kappa_s (Skalak only)
  double viscosity_ratio = 1.0;  ///< lambda = inner / outer viscosity (1: no contrast field)
  double strain = 4.0;           ///< gammadot t at the end of the run
  std::int64_t steps = 0;        ///< if > 0: run exactly this many steps instead of `strain`
  int sample_every = 50;         ///< steps between shape samples
  fluid::IbKernel kernel = fluid::IbKernel::kPeskin4;
  /// Membrane forces recomputed every force_every steps and held in between (spread at the
  /// nodes' current positions every step), as [coupling] force_every does in a coupled run.
  int force_every = 1;
  /// The spread force field held with the forces ([coupling] spread_held): spread at the
  /// positions of each force update only; with interpolation_held its weights too.
  bool spread_held = false;
  bool interpolation_held = false;
  CollisionKind collision = CollisionKind::kTrt;  ///< the lattice's collision operator
  Transport transport = Transport::inproc;
};

struct CapsuleShearRun {
  double gammadot = 0;       ///< shear rate [1/step]
  double wall_speed = 0;     ///< U = gammadot nz / 2
  double shear_modulus = 0;  ///< G_s [lattice force / lattice length]
  std::int64_t steps = 0;
  int nodes = 0, faces = 0;
  std::vector<double> strain;       ///< gammadot t of each sample
  std::vector<double> deformation;  ///< Taylor D in the x-z plane
  std::vector<double> inclination;  ///< angle of the long axis from x towards z [rad]
  std::vector<double> volume;       ///< enclosed volume / initial volume
  membrane::Points nodes_final;     ///< node positions after the last step
  /// Largest |sum of the spread force field - sum of the marker forces| / sum |marker forces|
  /// over the sampled steps (per component): the spreading's force conservation.
  double spread_error = 0;
  /// Largest |sum of the marker forces| / sum |marker forces|: the membrane's forces are internal.
  double net_force = 0;
  double wall_seconds = 0;
  /// With a viscosity contrast: fewest and most lattice nodes marked inside over the run, per
  /// initial enclosed volume (1 for a field that follows the capsule).
  double inside_min = 0, inside_max = 0;
};

/// G_s = mu gammadot a / (3 Ca) for Ca = mu gammadot a / E_s, E_s = 3 G_s
/// (reference/README.md, capsule_shear).
double shear_modulus_for(double capillary, double mu, double gammadot, double radius);

/// Runs the capsule in shear; throws std::runtime_error with both sides' messages if either fails.
CapsuleShearRun run_capsule_shear(const CapsuleShearSetup& setup);

/// Mean of D over the samples with strain >= from (the steady value once settled).
double mean_deformation(const CapsuleShearRun& run, double from);

}  // namespace dld::validation
