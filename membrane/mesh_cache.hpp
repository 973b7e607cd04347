// SPDX-License-Identifier: MIT
// Evans-Fung meshes cached on disk (OFF), keyed by their parameters, so runs and tests mesh once.
#pragma once
#include <string>

#include "membrane/evans_fung.hpp"
#include "membrane/mesh.hpp"

namespace dld::membrane {

/// Cache folder: $DLD_MESH_CACHE if set, else "cache/meshes" (relative to the working directory).
std::string default_mesh_cache_dir();

/// The mesh of `shape` with about `target_faces` faces, read from `cache_dir` if present, else made
/// with CGAL, validated and stored. Meshes are cached at unit radius and scaled to shape.radius, so
/// the key is (face count, C0, C2, C4). An empty cache_dir disables the cache.
TriMesh evans_fung_mesh(const EvansFungShape& shape, int target_faces,
                        const std::string& cache_dir = default_mesh_cache_dir());

/// The file name a given key is cached under (inside cache_dir).
std::string mesh_cache_name(const EvansFungShape& shape, int target_faces);

}  // namespace dld::membrane
