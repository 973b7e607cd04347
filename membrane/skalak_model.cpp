// SPDX-License-Identifier: MIT
#include "membrane/skalak_model.hpp"

#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const SkalakLaw& checked(const SkalakLaw& l) {
  if (!(l.p.kappa_s > 0.0) || !std::isfinite(l.p.kappa_s))
    throw InputError(fmt::format("skalak model: kappa_s must be positive, got {}", l.p.kappa_s));
  if (!(l.p.kappa_alpha >= 0.0) || !std::isfinite(l.p.kappa_alpha))
    throw InputError(
        fmt::format("skalak model: kappa_alpha must be >= 0, got {}", l.p.kappa_alpha));
  return l;
}
}  // namespace

SkalakModel::SkalakModel(const TriMesh& reference, const SkalakParams& p)
    : TriangleElements<SkalakLaw>(reference, checked(SkalakLaw{p}), "skalak") {}

SkalakModel SkalakModel::from_scene(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = required_table(t, kName);
  const bool ratio = s.has("area_ratio"), ref = s.has("area_modulus_ref_lu");
  if (ratio == ref)
    s.fail(ratio ? "area_ratio" : "area_modulus_ref_lu",
           "give exactly one of area_ratio (C = kappa_alpha/kappa_s) and area_modulus_ref_lu");
  // area_modulus_ref_lu is kappa_alpha at the reference setting: it fixes C there, and every
  // setting keeps that C (SPEC 9), so a setting never changes the cell.
  const double C = ratio ? s.in_range("area_ratio", 0.0, 1e6)
                         : s.in_range("area_modulus_ref_lu", 0.0, 1e6) / c.reference_kappa_s_lu;
  return SkalakModel(c.reference, {c.kappa_s_lu, C * c.kappa_s_lu});
}

SkalakModel SkalakModel::for_test(const TriMesh& reference) {
  return SkalakModel(reference, {1.0, 2.0});
}

std::string SkalakModel::describe() const {
  return fmt::format("skalak: kappa_s {:.6g}, kappa_alpha {:.6g} (lattice modulus), C = {:.6g}",
                     law().p.kappa_s, law().p.kappa_alpha, law().p.kappa_alpha / law().p.kappa_s);
}

}  // namespace dld::membrane
