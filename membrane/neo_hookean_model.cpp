// SPDX-License-Identifier: MIT
#include "membrane/neo_hookean_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const NeoHookeanLaw& checked(const NeoHookeanLaw& l) {
  if (!(l.p.shear_modulus > 0.0) || !std::isfinite(l.p.shear_modulus))
    throw InputError(fmt::format("neo_hookean model: shear modulus must be positive, got {}",
                                 l.p.shear_modulus));
  return l;
}
}  // namespace

NeoHookeanModel::NeoHookeanModel(const TriMesh& reference, const NeoHookeanParams& p)
    : TriangleElements<NeoHookeanLaw>(reference, checked(NeoHookeanLaw{p}), "neo_hookean") {}

NeoHookeanModel NeoHookeanModel::from_scene(const std::optional<TomlSection>& /*t*/,
                                            const ModelContext& c) {
  // G_s = kappa_s / 3: the same small-strain shear modulus as the Skalak law, so E_s = 3 G_s
  // = kappa_s and capsule capillary numbers use kappa_s directly. No keys of its own.
  return NeoHookeanModel(c.reference, {c.kappa_s_lu / 3.0});
}

NeoHookeanModel NeoHookeanModel::for_test(const TriMesh& reference) {
  return NeoHookeanModel(reference, {1.0});
}

std::string NeoHookeanModel::describe() const {
  return fmt::format("neo_hookean: G_s {:.6g} (lattice modulus)", law().p.shear_modulus);
}

}  // namespace dld::membrane
