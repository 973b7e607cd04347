// SPDX-License-Identifier: MIT
// Area barrier per triangle: keeps resisting where Skalak's area term gives way. Skalak's area
// energy (kappa_alpha/12)(J^2 - 1)^2, J = A/A_rest, resists compression with a tension
// ~ J (1 - J^2) that peaks at J = 1/sqrt(3) and vanishes as J -> 0, so a triangle compressed past
// there collapses (docs/results-history.md, "Why the dense runs go unstable late"). This term adds,
// per reference area,
//   w(J) = (kappa_b/2) (J_b - J)^2 for J < J_b, 0 otherwise,
// which is zero (with its force) for every triangle at J >= J_b: a cell whose triangles all stay
// there moves exactly as without it. Skalak's isotropic area energy has d2w/dJ2 = kappa_alpha
// (J^2 - 1/3), so with J_b >= 1/sqrt(3) and kappa_b >= kappa_alpha/3 their sum is convex in J on
// (0, 1]: the resistance grows all the way to J = 0 (there kappa_b J_b). A local area term that
// keeps a triangle from collapsing is what HemoCell's RBC model has (Zavodszky et al., Front.
// Physiol. 8 (2017) 563: a local area force that diverges at +-30 %); this one acts only below J_b,
// where Skalak's law fails.
#pragma once
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "membrane/model_context.hpp"
#include "membrane/triangle_elements.hpp"

namespace dld::membrane {

struct AreaBarrierParams {
  double modulus = 0.0;  ///< kappa_b [lattice modulus, energy/area]
  double below = 0.0;    ///< J_b: acts on triangles with A/A_rest below this [-], in (0, 1]
};

struct AreaBarrierLaw {
  AreaBarrierParams p;
  /// J = A/A_rest = sqrt(det C) = sqrt(1 + I2).
  static double area_ratio(double i2) { return std::sqrt(std::max(1.0 + i2, 0.0)); }
  double energy(double /*i1*/, double i2) const {
    const double gap = std::max(p.below - area_ratio(i2), 0.0);
    return 0.5 * p.modulus * gap * gap;
  }
  /// dw/dI2 = (dw/dJ) / (2 J); the node forces carry a factor dI2/dx ~ J, so they stay finite
  /// as J -> 0. I2 = det C - 1 has an absolute round-off of ~1e-16, so J below ~1e-8 is not
  /// resolved: below J = 1e-6 the force fades linearly to 0 instead of amplifying round-off.
  void derivatives(double /*i1*/, double i2, double& w1, double& w2) const {
    const double j = area_ratio(i2), gap = std::max(p.below - j, 0.0);
    w1 = 0.0;
    w2 = -p.modulus * gap / (2.0 * std::max(j, 1e-6));
  }
};

class AreaBarrier : public TriangleElements<AreaBarrierLaw> {
 public:
  static constexpr std::string_view kName = "area_barrier";
  /// Throws InputError unless kappa_b >= 0 and J_b in (0, 1].
  AreaBarrier(const TriMesh& reference, const AreaBarrierParams& p);
  static constexpr std::string_view kSummary =
      "area barrier per triangle below A/A_rest = J_b (kappa_b)";
  /// Reads [membrane.{kName}] (keys: docs/membrane-scene-keys.md) into lattice parameters.
  static AreaBarrier from_scene(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// kappa_b 1, J_b 1 on `reference` (acting on every compressed triangle), for the tests every
  /// model must pass.
  static AreaBarrier for_test(const TriMesh& reference);
  /// One line with its lattice parameters.
  std::string describe() const;
};

}  // namespace dld::membrane
