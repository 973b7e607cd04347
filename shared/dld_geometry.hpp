// SPDX-License-Identifier: MIT
// The DLD unit cell (SPEC section 2): a lambda x lambda x H box with one circular pillar in its
// middle, periodic in y, shifted periodic in x (leaving at x = lambda at height y re-enters at
// x = 0 at height y - d), no-slip walls at z = 0 and z = H.
// Units: whatever the caller constructs it with (um for physical, nodes for lattice).
#pragma once
#include <array>

namespace dld {

struct DldCell {
  double lambda = 32.0;  ///< centre-to-centre pillar distance (box side in x and y)
  double radius = 10.0;  ///< pillar radius
  double depth = 4.8;    ///< device depth H (walls at z = 0 and z = H)
  double shift = 4.4;    ///< row shift d

  double gap() const { return lambda - 2.0 * radius; }
  double pillar_x() const { return 0.5 * lambda; }
  double pillar_y() const { return 0.5 * lambda; }
  /// The same cell with every length multiplied by s (e.g. 1/dx to go to lattice units).
  DldCell scaled(double s) const { return {lambda * s, radius * s, depth * s, shift * s}; }
  /// Signed distance from (x, y) to the pillar surface in the x-y plane; negative inside.
  /// Uses the nearest periodic image of the pillar, so it is valid anywhere in the box.
  double pillar_distance(double x, double y) const;
  /// False only where pillar_distance(x, y) >= range for sure (every pillar image is at least
  /// radius + range away along x or y): callers skip the square roots for the nodes far away.
  bool pillar_within(double x, double y, double range) const;
  bool inside_pillar(double x, double y) const { return pillar_distance(x, y) < 0.0; }
};

/// Position folded into the box plus the number of x and y boundary crossings it took.
struct Wrapped {
  std::array<double, 3> position;
  int crossings_x = 0;  ///< +1 for each wrap through x = lambda (frame moves up by d)
  int crossings_y = 0;  ///< +1 for each wrap through y = lambda
};

/// Folds a point into [0, lambda) x [0, lambda) honouring the shift (z untouched).
Wrapped wrap_into_box(const DldCell& cell, std::array<double, 3> p);

/// Device coordinates of a box position after (kx, ky) crossings (SPEC section 7):
/// x + kx lambda, y + kx d + ky lambda.
std::array<double, 3> device_position(const DldCell& cell, const std::array<double, 3>& box, int kx,
                                      int ky);

}  // namespace dld
