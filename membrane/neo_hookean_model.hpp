// SPDX-License-Identifier: MIT
// Neo-Hookean membrane on linear triangles (thin-shell limit of an incompressible neo-Hookean
// solid; Barthes-Biesel, Diaz, Dhenin, J. Fluid Mech. 460 (2002) 211, eq. 2.7):
//   w = (G_s/2) (l1^2 + l2^2 + 1/(l1^2 l2^2) - 3) = (G_s/2) (I1 - 1 + 1/(1 + I2)).
#pragma once
#include <optional>
#include <string>
#include <string_view>

#include "membrane/model_context.hpp"
#include "membrane/triangle_elements.hpp"

namespace dld::membrane {

struct NeoHookeanParams {
  double shear_modulus = 0.0;  ///< G_s [lattice modulus]
};

struct NeoHookeanLaw {
  NeoHookeanParams p;
  double energy(double i1, double i2) const {
    return 0.5 * p.shear_modulus * (i1 - 1.0 + 1.0 / (1.0 + i2));
  }
  void derivatives(double /*i1*/, double i2, double& w1, double& w2) const {
    w1 = 0.5 * p.shear_modulus;
    w2 = -0.5 * p.shear_modulus / ((1.0 + i2) * (1.0 + i2));
  }
};

class NeoHookeanModel : public TriangleElements<NeoHookeanLaw> {
 public:
  static constexpr std::string_view kName = "neo_hookean";
  /// Throws InputError unless G_s > 0.
  NeoHookeanModel(const TriMesh& reference, const NeoHookeanParams& p);
  static constexpr std::string_view kSummary = "neo-Hookean finite elements (G_s = kappa_s/3)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static NeoHookeanModel from_scene(const std::optional<TomlSection>& table,
                                    const ModelContext& ctx);
  /// Moduli of order one on `reference`, for the tests every model must pass.
  static NeoHookeanModel for_test(const TriMesh& reference);
  /// One line with its lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
  std::string describe() const;
};

}  // namespace dld::membrane
