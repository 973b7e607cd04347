// SPDX-License-Identifier: MIT
// The membrane models, chosen by name in the scene ([membrane] models = [...]). A model is one
// file (the physics, with a Params struct) plus one line in kModels and one alternative in
// AnyModel below. Dispatch is a std::visit per model per evaluation, never per node.
#pragma once
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "membrane/area_penalty.hpp"
#include "membrane/bending_model.hpp"
#include "membrane/neo_hookean_model.hpp"
#include "membrane/skalak_model.hpp"
#include "membrane/volume_penalty.hpp"
#include "shared/toml_section.hpp"

namespace dld::membrane {

using AnyModel =
    std::variant<SkalakModel, NeoHookeanModel, BendingModel, VolumePenalty, AreaPenalty>;

/// What a model needs besides its own table to get lattice parameters.
struct ModelContext {
  const TriMesh& reference;  ///< rest shape [lattice units]
  double kappa_s_lu;         ///< the cell's Skalak kappa_s [lattice modulus]
  double radius_lu;          ///< cell radius r [lattice lengths]
  /// The same cell's kappa_s in lattice units of the reference setting (SPEC 4: dx 0.4 um,
  /// tau 1, Re 0.1; same Ca): a modulus given there is kappa_s_lu * (value / this).
  double reference_kappa_s_lu;
  double energy_to_lu;      ///< factor: J -> lattice energy
  double capillary_number;  ///< the scene's Ca; 0 when kappa_s was given directly
};

struct ModelEntry {
  std::string_view name;
  std::string_view summary;  ///< one line for docs and error messages
  /// Reads [membrane.<name>] (absent table = std::nullopt) and builds the model.
  AnyModel (*make)(const std::optional<TomlSection>& table, const ModelContext& ctx);
};

/// The registry: every model the scene can name.
const std::vector<ModelEntry>& model_registry();
/// Names joined for messages: "skalak, neo_hookean, ...".
std::string model_names();

/// Builds one model by name; unknown names throw InputError via `where.fail(key, ...)`.
AnyModel make_model(const std::string& name, const TomlSection& where, std::string_view key,
                    const std::optional<TomlSection>& table, const ModelContext& ctx);

/// The models of one cell type acting together.
class MembraneMechanics {
 public:
  MembraneMechanics() = default;
  MembraneMechanics(std::vector<std::string> names, std::vector<AnyModel> models);
  /// Adds -dE/dx of all models to f, returns the total energy.
  double add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const;
  double energy(const Eigen::Ref<const Points>& x) const;
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<AnyModel>& models() const { return models_; }

 private:
  std::vector<std::string> names_;
  std::vector<AnyModel> models_;
};

}  // namespace dld::membrane

namespace dld::membrane {
/// One line with the model's lattice parameters, e.g. "skalak: kappa_s 1e-4, kappa_alpha 0.5".
std::string describe(const AnyModel& model);
}  // namespace dld::membrane
