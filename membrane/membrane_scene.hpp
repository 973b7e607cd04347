// SPDX-License-Identifier: MIT
// The [membrane] and [cells] tables of a scene (keys: docs/membrane-scene-keys.md), turned into
// lattice-unit parameters through the scene's LatticeUnits, and the cells they describe.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "membrane/cell_set.hpp"
#include "membrane/contact.hpp"
#include "membrane/evans_fung.hpp"
#include "membrane/model_registry.hpp"
#include "membrane/packing_cache.hpp"
#include "membrane/relaxation.hpp"
#include "membrane/stretching.hpp"
#include "shared/column_tracker.hpp"
#include "shared/scene.hpp"

namespace dld::membrane {

/// [membrane.stretch]: optical-tweezers run without fluid.
struct StretchTask {
  std::vector<double> forces_pN;  ///< total force per end [pN]
  StretchOptions options;         ///< lattice units
  std::string output_csv;         ///< "" = none
};

/// [membrane.relax]: a cell deformed by an area-preserving in-plane stretch relaxes back.
struct RelaxTask {
  double initial_stretch = 1.2;  ///< x scaled by s, y by 1/s at the start [-]
  RelaxOptions options;          ///< lattice units
};

/// [cells] count = N: N cells packed at random (membrane/packing), saved and reused.
struct PackRequest {
  int count = 0;
  std::uint64_t seed = 1;
  std::string cache;          ///< folder of saved states ("" = pack every time)
  double clearance_lu = 1.0;  ///< smallest node gap: the contact range, else one lattice spacing
};

struct MembraneScene {
  EvansFungShape shape_um;  ///< rest shape [um]
  int mesh_faces = 2000;
  std::string mesh_cache;
  double kappa_s_N_per_m = 0.0;  ///< Skalak kappa_s [N/m]
  double kappa_s_lu = 0.0;
  double radius_lu = 0.0;
  TriMesh reference_lu;  ///< rest mesh, centred at the origin [lattice lengths]
  MembraneMechanics mechanics;
  std::optional<ContactParams> contact;  ///< lattice units
  std::vector<Eigen::Vector3d> centres_lu;
  std::vector<double> angles_rad;
  std::optional<PackRequest> pack;  ///< instead of centres_lu
  /// [cells] expected_mode (zigzag or displacement): what a single cell does in this device, when
  /// the scene states it; written into the run file, where dld-analyze prefers it to its map.
  std::optional<TransportMode> expected_mode;
  std::optional<StretchTask> stretch;
  std::optional<RelaxTask> relax;

  /// Lines with physical and lattice values, printed before a run.
  std::string describe(const Scene& scene) const;
};

/// Reads [membrane] and [cells] of `scene.document` (marking keys read) and meshes the cell
/// (through the cache). Throws InputError naming file, line and key.
MembraneScene read_membrane_scene(const Scene& scene);

/// The cells of the scene, in the scene's box (lattice units).
CellSet build_cells(const MembraneScene& m, const Scene& scene);

/// The packed state of `count` cells (the scene's [cells] count when 0) with the scene's seed,
/// cache, clearance and geometry; loaded when saved before, else packed and saved.
CachedPacking packed_scene_cells(const MembraneScene& m, const Scene& scene, int count = 0);

/// Ht = cells x cell volume / fluid volume of the box (pillar excluded), from the meshes.
double haematocrit(const CellSet& cells, const DldCell& box_lu);

}  // namespace dld::membrane
