// SPDX-License-Identifier: MIT
#include "membrane/packing_cache.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

// Bump when the packing algorithm or its constants change, so stale states are not reused.
constexpr const char* kVersion = "packing_v2";

struct Fnv1a {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  void number(double v) { bytes(&v, sizeof v); }
};

/// Everything the state depends on, as a hash of the exact bytes.
std::string key_of(const TriMesh& ref, const DldCell& box, const PackOptions& o) {
  Fnv1a f;
  f.bytes(kVersion, std::strlen(kVersion));
  f.bytes(ref.nodes.data(), sizeof(double) * static_cast<std::size_t>(ref.nodes.size()));
  f.bytes(ref.faces.data(), sizeof(Face) * ref.faces.size());
  for (double v : {box.lambda, box.radius, box.depth, box.shift, o.clearance, o.start_scale,
                   o.scale_step, static_cast<double>(o.count), static_cast<double>(o.seed),
                   static_cast<double>(o.max_iterations)})
    f.number(v);
  return fmt::format("{:016x}", f.h);
}

}  // namespace

std::string default_packing_cache_dir() {
  const char* env = std::getenv("DLD_PACKING_CACHE");
  return env && *env ? std::string(env) : std::string("cache/packings");
}

std::string packing_file_name(const TriMesh& reference, const DldCell& box, const PackOptions& o) {
  return fmt::format("{}_n{}_seed{}_{}.h5", kVersion, o.count, o.seed, key_of(reference, box, o));
}

void write_packing(const std::string& path, const PackedCells& p, const std::string& key) {
  const std::filesystem::path file(path);
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  // Per process: membrane processes of one run may pack the same state side by side.
  const std::string tmp = fmt::format("{}.{}.tmp", path, getpid());
  {
    H5File f(tmp, H5File::Mode::kCreate);
    f.write("/packing/positions", p.positions.data(),
            {static_cast<std::uint64_t>(p.positions.cols()), 3});
    const auto& r = p.report;
    f.attribute("/packing", "key", key);
    f.attribute("/packing", "units", std::string("lattice lengths"));
    f.attribute("/packing", "cells",
                static_cast<std::int64_t>(p.positions.cols() / p.nodes_per_cell));
    f.attribute("/packing", "nodes_per_cell", static_cast<std::int64_t>(p.nodes_per_cell));
    f.attribute("/packing", "stages", static_cast<std::int64_t>(r.stages));
    f.attribute("/packing", "iterations", static_cast<std::int64_t>(r.iterations));
    f.attribute("/packing", "seconds", r.seconds);
    f.attribute("/packing", "cpu_seconds", r.cpu_seconds);
    f.attribute("/packing", "gap_cells", r.gaps.cells);
    f.attribute("/packing", "gap_walls", r.gaps.walls);
    f.attribute("/packing", "gap_pillar", r.gaps.pillar);
  }
  std::filesystem::rename(tmp, path);
}

PackedCells read_packing(const std::string& path, const std::string& key, int count,
                         int nodes_per_cell) {
  H5File f(path, H5File::Mode::kRead);
  const std::string stored = f.read_attribute_string("/packing", "key");
  if (stored != key)
    throw InputError(fmt::format("{}: /packing key {} is not the expected {}", path, stored, key));
  PackedCells p;
  p.nodes_per_cell = static_cast<int>(f.read_attribute_number("/packing", "nodes_per_cell"));
  std::vector<std::uint64_t> dims;
  const std::vector<double> x = f.read("/packing/positions", &dims);
  const auto nodes = static_cast<std::uint64_t>(count) * static_cast<std::uint64_t>(nodes_per_cell);
  if (p.nodes_per_cell != nodes_per_cell || dims.size() != 2 || dims[0] != nodes || dims[1] != 3)
    throw InputError(fmt::format("{}: /packing/positions: expected {} cells of {} nodes", path,
                                 count, nodes_per_cell));
  p.positions = Eigen::Map<const Points>(x.data(), 3, static_cast<Eigen::Index>(nodes));
  auto& r = p.report;
  r.stages = static_cast<int>(f.read_attribute_number("/packing", "stages"));
  r.iterations = static_cast<int>(f.read_attribute_number("/packing", "iterations"));
  r.seconds = f.read_attribute_number("/packing", "seconds");
  r.cpu_seconds = f.read_attribute_number("/packing", "cpu_seconds");
  r.gaps = {f.read_attribute_number("/packing", "gap_cells"),
            f.read_attribute_number("/packing", "gap_walls"),
            f.read_attribute_number("/packing", "gap_pillar")};
  return p;
}

CachedPacking packed_cells(const TriMesh& reference, const DldCell& box, const PackOptions& o,
                           const std::string& cache_dir, const PackLog& log) {
  TriMesh ref = reference;
  ref.nodes.colwise() -= centroid(ref.nodes);
  CachedPacking out;
  const std::string key = key_of(ref, box, o);
  if (!cache_dir.empty())
    out.file = (std::filesystem::path(cache_dir) / packing_file_name(ref, box, o)).string();
  if (!out.file.empty() && std::filesystem::exists(out.file)) {
    out.cells = read_packing(out.file, key, o.count, ref.node_count());
    out.from_cache = true;
    return out;
  }
  out.cells = pack_cells(ref, box, o, log);
  if (!out.file.empty()) write_packing(out.file, out.cells, key);
  return out;
}

}  // namespace dld::membrane
