// SPDX-License-Identifier: MIT
#include "membrane/mesh_cache.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <filesystem>

#include "membrane/cgal_mesher.hpp"

namespace dld::membrane {

std::string default_mesh_cache_dir() {
  const char* env = std::getenv("DLD_MESH_CACHE");
  return env && *env ? std::string(env) : std::string("cache/meshes");
}

std::string mesh_cache_name(const EvansFungShape& shape, int target_faces) {
  // v2 (fixed CGAL seed): bump when the meshing pipeline changes so stale files are not reused.
  return fmt::format("evans_fung_v2_f{}_c{:.6g}_{:.6g}_{:.6g}.off", target_faces, shape.c0,
                     shape.c2, shape.c4);
}

TriMesh evans_fung_mesh(const EvansFungShape& shape, int target_faces,
                        const std::string& cache_dir) {
  EvansFungShape unit = shape;
  unit.radius = 1.0;
  TriMesh mesh;
  const std::string path =
      cache_dir.empty()
          ? std::string()
          : (std::filesystem::path(cache_dir) / mesh_cache_name(unit, target_faces)).string();
  if (!path.empty() && std::filesystem::exists(path)) {
    mesh = read_off(path);
    validate_closed_surface(mesh, path);
  } else {
    spdlog::info("meshing Evans-Fung cell with CGAL: {} faces", target_faces);
    mesh = mesh_evans_fung_cgal(unit, target_faces);
    validate_closed_surface(mesh, "CGAL Evans-Fung mesh");
    if (!path.empty()) write_off(mesh, path);
  }
  mesh.nodes *= shape.radius;
  return mesh;
}

}  // namespace dld::membrane
