// SPDX-License-Identifier: MIT
#include "membrane/model_registry.hpp"

#include <fmt/format.h>

namespace dld::membrane {
namespace {

/// One registry row per alternative of AnyModel, from the model's own kName, kSummary,
/// from_scene() and for_test().
template <typename... Model>
std::vector<ModelEntry> entries(const std::variant<Model...>* /*type*/) {
  return {ModelEntry{
      Model::kName, Model::kSummary,
      [](const std::optional<TomlSection>& t, const ModelContext& c) -> AnyModel {
        return Model::from_scene(t, c);
      },
      [](const TriMesh& reference) -> AnyModel { return Model::for_test(reference); }}...};
}

}  // namespace

const std::vector<ModelEntry>& model_registry() {
  static const std::vector<ModelEntry> kModels = entries(static_cast<const AnyModel*>(nullptr));
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

std::string describe(const AnyModel& model) {
  return std::visit([](const auto& m) { return m.describe(); }, model);
}

}  // namespace dld::membrane
