// SPDX-License-Identifier: MIT
// The handshake identity of a scene, built the same way by every program of a coupled run.
#pragma once
#include <cstdint>

#include "coupler/handshake.hpp"
#include "shared/scene.hpp"

namespace dld::coupler {

inline SceneIdentity scene_identity(const Scene& scene, std::uint32_t total_cells) {
  const LatticeUnits u = scene.units();
  SceneIdentity id;
  id.scene_hash = scene.hash;
  // Units and geometry, named for the messages ("handshake: field 'dt_s': fluid has ..."); the
  // coupler compares them by name and knows nothing of what they mean.
  constexpr double tolerance = 1e-12;
  id.agreed = {{"dx_m", u.dx_m(), tolerance},
               {"dt_s", u.dt_s(), tolerance},
               {"density_kg_m3", u.rho_kg_m3(), tolerance},
               {"lambda_m", scene.cell_um.lambda * 1e-6, tolerance},
               {"radius_m", scene.cell_um.radius * 1e-6, tolerance},
               {"depth_m", scene.cell_um.depth * 1e-6, tolerance},
               {"shift_m", scene.cell_um.shift * 1e-6, tolerance}};
  id.total_cells = total_cells;
  return id;
}

}  // namespace dld::coupler
