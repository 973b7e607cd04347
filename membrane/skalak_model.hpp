// SPDX-License-Identifier: MIT
// Skalak membrane on linear triangles. Strain energy per reference area (Skalak et al., Biophys.
// J. 13 (1973) 245, in the form of Krueger's finite-element membrane):
//   w = (kappa_s/12)(I1^2 + 2 I1 - 2 I2) + (kappa_alpha/12) I2^2,
// shear modulus G_s = kappa_s/3 and C = kappa_alpha/kappa_s in Barthes-Biesel's notation.
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include "membrane/model_context.hpp"
#include "membrane/triangle_elements.hpp"

namespace dld::membrane {

struct SkalakParams {
  double kappa_s = 0.0;      ///< shear parameter [lattice modulus, force/length]
  double kappa_alpha = 0.0;  ///< area-dilation parameter [lattice modulus]
};

struct SkalakLaw {
  SkalakParams p;
  double energy(double i1, double i2) const {
    return p.kappa_s / 12.0 * (i1 * i1 + 2.0 * i1 - 2.0 * i2) + p.kappa_alpha / 12.0 * i2 * i2;
  }
  void derivatives(double i1, double i2, double& w1, double& w2) const {
    w1 = p.kappa_s / 6.0 * (i1 + 1.0);
    w2 = -p.kappa_s / 6.0 + p.kappa_alpha / 6.0 * i2;
  }
};

class SkalakModel : public TriangleElements<SkalakLaw> {
 public:
  static constexpr std::string_view kName = "skalak";
  /// Throws InputError unless kappa_s > 0 and kappa_alpha >= 0.
  SkalakModel(const TriMesh& reference, const SkalakParams& p);
  static constexpr std::string_view kSummary = "Skalak finite elements (kappa_s, kappa_alpha)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static SkalakModel from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// Moduli of order one on `reference`, for the tests every model must pass.
  static SkalakModel for_test(const TriMesh& reference);
  /// One line with its lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
  std::string describe() const;
};

}  // namespace dld::membrane
