// SPDX-License-Identifier: MIT
#include "membrane/area_barrier.hpp"

#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const AreaBarrierLaw& checked(const AreaBarrierLaw& l) {
  if (!(l.p.modulus >= 0.0) || !std::isfinite(l.p.modulus))
    throw InputError(fmt::format("area_barrier model: modulus must be >= 0, got {}", l.p.modulus));
  if (!(l.p.below > 0.0 && l.p.below <= 1.0))
    throw InputError(fmt::format("area_barrier model: J_b must be in (0, 1], got {}", l.p.below));
  return l;
}
}  // namespace

AreaBarrier::AreaBarrier(const TriMesh& reference, const AreaBarrierParams& p)
    : TriangleElements<AreaBarrierLaw>(reference, checked(AreaBarrierLaw{p}), "area_barrier") {}

AreaBarrier AreaBarrier::from_scene(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = required_table(t, kName);
  // Given at the reference setting, as Skalak's area_modulus_ref_lu: the same ratio to kappa_s at
  // every setting (SPEC 4), so a setting never changes the cell.
  const double ref = s.in_range("modulus_ref_lu", 0.0, 1e6);
  const double below = s.in_range("below", 1e-3, 1.0);
  return AreaBarrier(c.reference, {ref / c.reference_kappa_s_lu * c.kappa_s_lu, below});
}

AreaBarrier AreaBarrier::for_test(const TriMesh& reference) {
  return AreaBarrier(reference, {1.0, 1.0});
}

std::string AreaBarrier::describe() const {
  return fmt::format("area_barrier: kappa_b {:.6g} (lattice modulus) below A/A_rest = {:.6g}",
                     law().p.modulus, law().p.below);
}

}  // namespace dld::membrane
