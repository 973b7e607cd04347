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

}  // namespace dld::membrane
