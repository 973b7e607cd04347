// SPDX-License-Identifier: MIT
#include "membrane/run_checkpoint.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {

void write_run_checkpoint(const std::string& path, const RunCheckpoint& c) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  const std::string tmp = path + ".tmp";
  {
    H5File f(tmp, H5File::Mode::kCreate);
    f.write("/membrane/positions", c.positions.data(),
            {static_cast<std::uint64_t>(c.positions.cols()), 3});
    f.write("/membrane/samples", c.rows);
    f.attribute("/membrane", "step", c.step);
    f.attribute("/membrane", "scene_hash", c.scene_hash);
    f.attribute("/membrane", "first_cell", static_cast<std::int64_t>(c.first_cell));
    f.attribute("/membrane", "cells", static_cast<std::int64_t>(c.cells));
    f.attribute("/membrane", "nodes_per_cell", static_cast<std::int64_t>(c.nodes_per_cell));
  }
  if (std::filesystem::exists(path)) std::filesystem::rename(path, path + ".prev");
  std::filesystem::rename(tmp, path);
}

RunCheckpoint read_run_checkpoint(const std::string& path, const RunCheckpoint& expected) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: no such checkpoint", path));
  H5File f(path, H5File::Mode::kRead);
  RunCheckpoint c;
  c.scene_hash = f.read_attribute_string("/membrane", "scene_hash");
  if (c.scene_hash != expected.scene_hash)
    throw InputError(fmt::format("{}: /membrane scene_hash {} is not the scene's {}", path,
                                 c.scene_hash, expected.scene_hash));
  auto integer = [&](const char* name, int want) {
    const auto v = static_cast<int>(f.read_attribute_number("/membrane", name));
    if (v != want)
      throw InputError(
          fmt::format("{}: /membrane {} is {}, this process has {}", path, name, v, want));
    return v;
  };
  c.first_cell = integer("first_cell", expected.first_cell);
  c.cells = integer("cells", expected.cells);
  c.nodes_per_cell = integer("nodes_per_cell", expected.nodes_per_cell);
  c.step = static_cast<std::int64_t>(f.read_attribute_number("/membrane", "step"));
  std::vector<std::uint64_t> dims;
  const std::vector<double> x = f.read("/membrane/positions", &dims);
  const auto nodes =
      static_cast<std::uint64_t>(c.cells) * static_cast<std::uint64_t>(c.nodes_per_cell);
  if (dims.size() != 2 || dims[0] != nodes || dims[1] != 3)
    throw InputError(fmt::format("{}: /membrane/positions: expected {} x 3 values", path, nodes));
  c.positions = Eigen::Map<const Points>(x.data(), 3, static_cast<Eigen::Index>(nodes));
  c.rows = f.read("/membrane/samples");
  const std::size_t width = 1 + 4 * static_cast<std::size_t>(c.cells);
  if (c.rows.empty() || c.rows.size() % width != 0)
    throw InputError(fmt::format("{}: /membrane/samples: expected rows of {} values", path, width));
  return c;
}

}  // namespace dld::membrane
