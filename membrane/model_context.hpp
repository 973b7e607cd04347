// SPDX-License-Identifier: MIT
// What a membrane model reads besides its own [membrane.<name>] table to get its lattice
// parameters (membrane/model_registry.hpp): every model's from_scene() takes it.
#pragma once
#include <fmt/format.h>

#include <optional>
#include <string_view>

#include "membrane/mesh.hpp"
#include "shared/input_error.hpp"
#include "shared/toml_section.hpp"

namespace dld::membrane {

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

/// The model's table, which it requires: a missing one is an InputError naming it.
inline const TomlSection& required_table(const std::optional<TomlSection>& t,
                                         std::string_view model) {
  if (!t)
    throw InputError(
        fmt::format("scene: table [membrane.{}] is required by model '{}'", model, model));
  return *t;
}

}  // namespace dld::membrane
