// SPDX-License-Identifier: MIT
// Shape of a deformed capsule from the inertia tensor of the volume its membrane encloses: the
// ellipsoid with the same volume second moments, and the Taylor deformation parameter
// D = (L - B)/(L + B) of its section in the shear plane (Taylor, Proc. R. Soc. A 146 (1934) 501;
// the measure of Ramanujan & Pozrikidis, J. Fluid Mech. 361 (1998) 117).
// Lengths in the units of the positions (lattice lengths in the coupled runs).
#pragma once
#include <Eigen/Core>

#include "membrane/mesh.hpp"

namespace dld::membrane {

/// The equivalent ellipsoid: a solid ellipsoid with semi-axes (a, b, c) has the second-moment
/// tensor M = integral over the volume of (x - c)(x - c)^T = (V/5) diag(a^2, b^2, c^2) in its
/// principal frame, so the semi-axes are sqrt(5 m_i / V) for the eigenvalues m_i of M.
struct InertiaEllipsoid {
  Eigen::Vector3d centre;     ///< volume centroid
  double volume = 0.0;        ///< enclosed volume (divergence theorem)
  Eigen::Vector3d semi_axes;  ///< descending
  Eigen::Matrix3d axes;       ///< unit principal axes, column i belongs to semi_axes(i)
};

/// M and V by splitting the closed surface into tetrahedra (volume centroid, face) and summing
/// the exact tetrahedron moments: for vertices 0, p1, p2, p3 with signed volume v,
/// integral x x^T = (v/20) (sum p_k p_k^T + (sum p_k)(sum p_k)^T) (Tonon, J. Math. Stat. 1 (2005)
/// 8).
InertiaEllipsoid inertia_ellipsoid(const TriMesh& mesh, const Points& x);

/// Taylor deformation in the plane normal to `vorticity_axis` (unit vector along the flow's
/// vorticity: +y for u_x = gammadot z): of the three
/// principal axes, the one closest to the vorticity axis is left out; L and B are the larger and
/// smaller semi-axis of the other two.
struct ShearPlaneShape {
  double deformation = 0.0;  ///< D = (L - B)/(L + B)
  double long_axis = 0.0;    ///< L
  double short_axis = 0.0;   ///< B
  /// Angle of the L axis from `flow_axis` towards the gradient axis flow x vorticity, in
  /// (-pi/2, pi/2] [rad]; about +pi/4 at the start of a simple shear.
  double inclination = 0.0;
};
ShearPlaneShape shear_plane_shape(const InertiaEllipsoid& e, const Eigen::Vector3d& flow_axis,
                                  const Eigen::Vector3d& vorticity_axis);

}  // namespace dld::membrane
