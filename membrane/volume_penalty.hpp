// SPDX-License-Identifier: MIT
// Global volume penalty E_V = (kappa_V/2)(V - V0)^2 / V0 (Krueger, Varnik, Raabe, Comput. Math.
// Appl. 61 (2011) 3485, eq. 14), V from the divergence theorem over the faces.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "membrane/mesh.hpp"
#include "membrane/model_context.hpp"

namespace dld::membrane {

struct VolumeParams {
  double kappa_v = 0.0;  ///< [lattice energy / lattice volume]
};

class VolumePenalty {
 public:
  static constexpr std::string_view kName = "volume";
  /// Throws InputError unless kappa_V >= 0 and the reference volume is positive.
  VolumePenalty(const TriMesh& reference, const VolumeParams& p);
  static constexpr std::string_view kSummary = "global volume penalty (kappa_V)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static VolumePenalty from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// Moduli of order one on `reference`, for the tests every model must pass.
  static VolumePenalty for_test(const TriMesh& reference);
  /// One line with its lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
  std::string describe() const;
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
