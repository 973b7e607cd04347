// SPDX-License-Identifier: MIT
// Scene keys of each model: read here so that the physics files stay free of scene parsing.
#include "membrane/model_registry.hpp"

#include <fmt/format.h>

namespace dld::membrane {
namespace {

const TomlSection& need(const std::optional<TomlSection>& t, std::string_view model) {
  if (!t)
    throw InputError(
        fmt::format("scene: table [membrane.{}] is required by model '{}'", model, model));
  return *t;
}

AnyModel make_skalak(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = need(t, "skalak");
  const bool ratio = s.has("area_ratio"), ref = s.has("area_modulus_ref_lu");
  if (ratio == ref)
    s.fail(ratio ? "area_ratio" : "area_modulus_ref_lu",
           "give exactly one of area_ratio (C = kappa_alpha/kappa_s) and area_modulus_ref_lu");
  // area_modulus_ref_lu is kappa_alpha at the reference setting: it fixes C there, and every
  // setting keeps that C (SPEC 9), so a setting never changes the cell.
  const double C = ratio ? s.in_range("area_ratio", 0.0, 1e6)
                         : s.in_range("area_modulus_ref_lu", 0.0, 1e6) / c.reference_kappa_s_lu;
  const double ka = C * c.kappa_s_lu;
  return SkalakModel(c.reference, {c.kappa_s_lu, ka});
}

AnyModel make_neo_hookean(const std::optional<TomlSection>& /*t*/, const ModelContext& c) {
  // G_s = kappa_s / 3: the same small-strain shear modulus as the Skalak law, so E_s = 3 G_s
  // = kappa_s and capsule capillary numbers use kappa_s directly. No keys of its own.
  return NeoHookeanModel(c.reference, {c.kappa_s_lu / 3.0});
}

AnyModel make_bending(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = need(t, "bending");
  const bool rel = s.has("modulus_rel"), joule = s.has("modulus_J");
  if (rel == joule)
    s.fail(
        rel ? "modulus_rel" : "modulus_J",
        "give exactly one of modulus_rel (kappa_b / (kappa_s r^2)) and modulus_J (kappa_b in J)");
  if (joule)
    return BendingModel(c.reference, {s.in_range("modulus_J", 0.0, 1e-15) * c.energy_to_lu});
  return BendingModel(c.reference, {s.in_range("modulus_rel", 0.0, 1e3) * c.kappa_s_lu *
                                    c.radius_lu * c.radius_lu});
}

AnyModel make_volume(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = need(t, "volume");
  const double rel = s.in_range("modulus_rel", 0.0, 1e9);
  // kappa_V relative to the kappa_s of another Ca: the same kappa_V at every Ca of a sweep (kappa_s
  // falls as 1/Ca at fixed drive), where a stiffness that follows kappa_s would weaken 5-fold
  // from Ca 0.2 to 1.0.
  double kappa_s = c.kappa_s_lu;
  if (s.has("reference_capillary_number")) {
    const double ref = s.positive("reference_capillary_number");
    if (!(c.capillary_number > 0.0)) {
      s.fail("reference_capillary_number",
             "needs [membrane] capillary_number (kappa_s was given directly)");
    }
    kappa_s *= c.capillary_number / ref;
  }
  return VolumePenalty(c.reference, {rel * kappa_s / c.radius_lu});
}

AnyModel make_area(const std::optional<TomlSection>& t, const ModelContext& c) {
  const double rel = need(t, "area").in_range("modulus_rel", 0.0, 1e9);
  return AreaPenalty(c.reference, {rel * c.kappa_s_lu});
}

}  // namespace

const std::vector<ModelEntry>& model_registry() {
  static const std::vector<ModelEntry> kModels{
      {SkalakModel::kName, "Skalak finite elements (kappa_s, kappa_alpha)", make_skalak},
      {NeoHookeanModel::kName, "neo-Hookean finite elements (G_s = kappa_s/3)", make_neo_hookean},
      {BendingModel::kName, "dihedral-angle bending (kappa_b)", make_bending},
      {VolumePenalty::kName, "global volume penalty (kappa_V)", make_volume},
      {AreaPenalty::kName, "global area penalty (kappa_A)", make_area},
  };
  return kModels;
}

std::string model_names() {
  std::string s;
  for (const auto& m : model_registry()) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

AnyModel make_model(const std::string& name, const TomlSection& where, std::string_view key,
                    const std::optional<TomlSection>& table, const ModelContext& ctx) {
  for (const auto& m : model_registry())
    if (m.name == name) return m.make(table, ctx);
  where.fail(key, fmt::format("unknown membrane model '{}' (known: {})", name, model_names()));
}

MembraneMechanics::MembraneMechanics(std::vector<std::string> names, std::vector<AnyModel> models)
    : names_(std::move(names)), models_(std::move(models)) {}

double MembraneMechanics::add_forces(const Eigen::Ref<const Points>& x,
                                     Eigen::Ref<Points> f) const {
  double e = 0.0;
  for (const auto& m : models_)
    e += std::visit([&](const auto& model) { return model.add_forces(x, f); }, m);
  return e;
}

double MembraneMechanics::energy(const Eigen::Ref<const Points>& x) const {
  double e = 0.0;
  for (const auto& m : models_)
    e += std::visit([&](const auto& model) { return model.energy(x); }, m);
  return e;
}

}  // namespace dld::membrane

namespace dld::membrane {

std::string describe(const AnyModel& model) {
  return std::visit(
      [](const auto& m) -> std::string {
        using T = std::decay_t<decltype(m)>;
        if constexpr (std::is_same_v<T, SkalakModel>)
          return fmt::format(
              "skalak: kappa_s {:.6g}, kappa_alpha {:.6g} (lattice modulus), C = {:.6g}",
              m.law().p.kappa_s, m.law().p.kappa_alpha, m.law().p.kappa_alpha / m.law().p.kappa_s);
        else if constexpr (std::is_same_v<T, NeoHookeanModel>)
          return fmt::format("neo_hookean: G_s {:.6g} (lattice modulus)", m.law().p.shear_modulus);
        else if constexpr (std::is_same_v<T, BendingModel>)
          return fmt::format("bending: kappa_b {:.6g} (lattice energy)", m.params().kappa_b);
        else if constexpr (std::is_same_v<T, VolumePenalty>)
          return fmt::format("volume: kappa_V {:.6g} (lattice energy/volume), V0 {:.6g}",
                             m.params().kappa_v, m.reference_volume());
        else
          return fmt::format("area: kappa_A {:.6g} (lattice modulus)", m.params().kappa_a);
      },
      model);
}

}  // namespace dld::membrane
