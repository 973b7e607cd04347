// SPDX-License-Identifier: MIT
// The solid/fluid layout of a box in lattice units: circular pillars (axis along z), optional
// no-slip walls at z = 0 and z = nz, periodic y, and x periodic with a lateral shift (what leaves
// through x = nx at height y re-enters at x = 0 at height y - shift). Node (i, j, k) sits at
// (i + 1/2, j + 1/2, k + 1/2), so half-way bounce-back puts walls on whole coordinates.
#pragma once
#include <array>
#include <vector>

#include "shared/dld_geometry.hpp"

namespace dld::fluid {

struct Pillar {
  double x, y, radius;  ///< lattice units
};

struct Domain {
  int nx = 0, ny = 0, nz = 0;
  double shift = 0.0;   ///< lattice units, any real value in [0, ny)
  bool walls_z = true;  ///< no-slip walls at z = 0 and z = nz; false: periodic z
  /// Tangential velocities of the walls at z = 0 and z = nz (lattice units): moving-wall
  /// bounce-back, e.g. for simple shear. Zero for the DLD device.
  std::array<double, 3> wall_velocity_low{0, 0, 0};
  std::array<double, 3> wall_velocity_high{0, 0, 0};
  std::vector<Pillar> pillars;
  /// Pillar walls: false = half-way bounce-back (wall half-way along each link, exact mass
  /// conservation); true = Bouzidi interpolated bounce-back (wall at its true distance).
  bool curved_walls = false;

  /// True if the point (x, y) lies in a pillar or one of its periodic (shifted) images.
  bool in_pillar(double x, double y) const;
  /// Node (i, j, k) may lie in the ghost layer (-1 or n); z outside [0, nz) is solid with walls.
  bool solid_node(int i, int j, int k) const;
  /// Fraction t in (0, 1] of the link from (x, y) along (cx, cy) at which it enters a pillar (or
  /// an image); 0.5 if the link does not cross a pillar surface in the plane.
  double pillar_link_fraction(double x, double y, int cx, int cy) const;
};

/// The DLD unit cell (SPEC section 2) on a lattice: one pillar in the middle of the box.
Domain dld_domain(const DldCell& cell_lu, int nx, int ny, int nz);

}  // namespace dld::fluid
