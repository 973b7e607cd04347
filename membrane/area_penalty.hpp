// SPDX-License-Identifier: MIT
// Global surface-area penalty E_A = (kappa_A/2)(A - A0)^2 / A0 (Krueger, Varnik, Raabe, Comput.
// Math. Appl. 61 (2011) 3485, eq. 13).
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "membrane/mesh.hpp"
#include "membrane/model_context.hpp"

namespace dld::membrane {

struct AreaParams {
  double kappa_a = 0.0;  ///< [lattice modulus, energy / area]
};

class AreaPenalty {
 public:
  static constexpr std::string_view kName = "area";
  /// Throws InputError unless kappa_A >= 0.
  AreaPenalty(const TriMesh& reference, const AreaParams& p);
  static constexpr std::string_view kSummary = "global area penalty (kappa_A)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static AreaPenalty from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// Moduli of order one on `reference`, for the tests every model must pass.
  static AreaPenalty for_test(const TriMesh& reference);
  /// One line with its lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
  std::string describe() const;
  double energy(const Eigen::Ref<const Points>& x) const;
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const;

  const AreaParams& params() const { return p_; }

 private:
  double area(const Eigen::Ref<const Points>& x) const;
  AreaParams p_;
  std::vector<Face> faces_;
  double a0_;
};

}  // namespace dld::membrane
