// SPDX-License-Identifier: MIT
// The Evans-Fung biconcave rest shape of a red blood cell (Evans & Fung, Microvasc. Res. 4 (1972)
// 335): z(rho) = +-(R/2) sqrt(1 - rho^2) (C0 + C2 rho^2 + C4 rho^4), rho = r/R, axis along z.
#pragma once

namespace dld::membrane {

struct EvansFungShape {
  double radius = 1.0;  ///< R, half the major diameter [any length unit]
  double c0 = 0.207;    ///< coefficients as fitted by the Krueger group's meshes [-]
  double c2 = 2.000;
  double c4 = -1.123;

  /// Half thickness z(rho) >= 0 at in-plane distance r from the axis (0 outside r >= R).
  double half_thickness(double r) const;
  /// Implicit function: negative inside, positive outside, zero on the surface.
  /// f = z^2 - z(rho)^2 for rho < 1 and grows with the distance outside.
  double implicit(double x, double y, double z) const;
  /// Area and volume of the smooth surface by quadrature (for mesh checks).
  double area() const;
  double volume() const;
  double max_thickness() const;
};

}  // namespace dld::membrane
