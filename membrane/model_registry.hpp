// SPDX-License-Identifier: MIT
// The membrane models, chosen by name in the scene ([membrane] models = [...]). A model is one
// file (membrane/<name>.hpp/.cpp: the physics with a Params struct, kName, kSummary, from_scene()
// reading its [membrane.<name>] table, for_test() and describe()) plus its include and its
// alternative in AnyModel below: the registry, the scene reader, describe() and the tests every
// model must pass (tests/membrane/models_test.cpp) all follow from AnyModel. Dispatch is a
// std::visit per model per evaluation, never per node.
#pragma once
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "membrane/area_barrier.hpp"
#include "membrane/area_penalty.hpp"
#include "membrane/bending_model.hpp"
#include "membrane/model_context.hpp"
#include "membrane/neo_hookean_model.hpp"
#include "membrane/skalak_model.hpp"
#include "membrane/spring_network.hpp"
#include "membrane/volume_penalty.hpp"
#include "shared/toml_section.hpp"

namespace dld::membrane {

using AnyModel = std::variant<SkalakModel, NeoHookeanModel, BendingModel, VolumePenalty,
                              AreaPenalty, SpringNetwork, AreaBarrier>;

struct ModelEntry {
  std::string_view name;
  std::string_view summary;  ///< one line for docs and error messages
  /// Reads [membrane.<name>] (absent table = std::nullopt) and builds the model.
  AnyModel (*make)(const std::optional<TomlSection>& table, const ModelContext& ctx);
  /// The model with moduli of order one on a test mesh.
  AnyModel (*for_test)(const TriMesh& reference);
};

/// The registry: every model the scene can name, in AnyModel's order.
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

/// One line with the model's lattice parameters (the model's describe()).
std::string describe(const AnyModel& model);

}  // namespace dld::membrane
