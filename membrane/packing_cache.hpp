// SPDX-License-Identifier: MIT
// Packed initial states saved to disk and reused: every run with the same cells, seed, geometry,
// mesh and clearance starts from the same state. One HDF5 file per state, named by a hash of
// everything that determines it.
#pragma once
#include <string>

#include "membrane/packing.hpp"

namespace dld::membrane {

/// Cache folder: $DLD_PACKING_CACHE if set, else "cache/packings" (relative to the working
/// directory).
std::string default_packing_cache_dir();

/// File name of the state of (reference, box, options): "packing_v2_n<count>_seed<seed>_<hash>.h5".
std::string packing_file_name(const TriMesh& reference, const DldCell& box, const PackOptions& o);

/// Writes atomically (temporary file, then rename): /packing/positions (nodes x 3, lattice
/// lengths) and the report as attributes.
void write_packing(const std::string& path, const PackedCells& p, const std::string& key);
/// Reads a state written by write_packing; throws InputError naming the file when its key, cell
/// count or node count differ from the expected ones.
PackedCells read_packing(const std::string& path, const std::string& key, int count,
                         int nodes_per_cell);

struct CachedPacking {
  PackedCells cells;
  std::string file;         ///< where it is stored ("" without a cache)
  bool from_cache = false;  ///< loaded rather than packed now
};

/// The state from `cache_dir` if present, else packed and stored there. An empty cache_dir packs
/// every time.
CachedPacking packed_cells(const TriMesh& reference, const DldCell& box, const PackOptions& o,
                           const std::string& cache_dir, const PackLog& log = {});

}  // namespace dld::membrane
