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
  id.dx_m = u.dx_m();
  id.dt_s = u.dt_s();
  id.density_kg_m3 = u.rho_kg_m3();
  id.lambda_m = scene.cell_um.lambda * 1e-6;
  id.radius_m = scene.cell_um.radius * 1e-6;
  id.depth_m = scene.cell_um.depth * 1e-6;
  id.shift_m = scene.cell_um.shift * 1e-6;
  id.total_cells = total_cells;
  return id;
}

}  // namespace dld::coupler
