// SPDX-License-Identifier: MIT
// Global volume penalty E_V = (kappa_V/2)(V - V0)^2 / V0 (Krueger, Varnik, Raabe, Comput. Math.
// Appl. 61 (2011) 3485, eq. 14), V from the divergence theorem over the faces.
#pragma once
#include <string_view>
#include <vector>

#include "membrane/mesh.hpp"

namespace dld::membrane {

struct VolumeParams {
  double kappa_v = 0.0;  ///< [lattice energy / lattice volume]
};

class VolumePenalty {
 public:
  static constexpr std::string_view kName = "volume";
  /// Throws InputError unless kappa_V >= 0 and the reference volume is positive.
  VolumePenalty(const TriMesh& reference, const VolumeParams& p);
  double energy(const Eigen::Ref<const Points>& x) const;
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const;
  double reference_volume() const { return v0_; }
  const VolumeParams& params() const { return p_; }

 private:
  double volume(const Eigen::Ref<const Points>& x) const;
  VolumeParams p_;
  std::vector<Face> faces_;
  double v0_;
};

}  // namespace dld::membrane
