// SPDX-License-Identifier: MIT
#include "membrane/run_checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

constexpr std::size_t kSampleValuesPerCell = 4;  // centroid x, y, z [um] and volume [um^3]

std::size_t row_width(int cells) {
  return 1 + kSampleValuesPerCell * static_cast<std::size_t>(cells);
}

/// One process's checkpoint as written, checked against the scene and the mesh only.
RunCheckpoint read_part(const std::string& path, const RunCheckpoint& expected) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: no such checkpoint", path));
  H5File f(path, H5File::Mode::kRead);
  RunCheckpoint c;
  c.scene_hash = f.read_attribute_string("/membrane", "scene_hash");
  if (c.scene_hash != expected.scene_hash)
    throw InputError(fmt::format("{}: /membrane scene_hash {} is not the scene's {}", path,
                                 c.scene_hash, expected.scene_hash));
  auto integer = [&](const char* name) {
    const double v = f.read_attribute_number("/membrane", name);
    if (v < 0 || v > 1e9 || v != static_cast<int>(v))
      throw InputError(fmt::format("{}: /membrane {} is {}, expected a count", path, name, v));
    return static_cast<int>(v);
  };
  c.first_cell = integer("first_cell");
  c.cells = integer("cells");
  c.nodes_per_cell = integer("nodes_per_cell");
  if (c.nodes_per_cell != expected.nodes_per_cell)
    throw InputError(fmt::format("{}: /membrane nodes_per_cell is {}, this process's mesh has {}",
                                 path, c.nodes_per_cell, expected.nodes_per_cell));
  c.step = static_cast<std::int64_t>(f.read_attribute_number("/membrane", "step"));
  std::vector<std::uint64_t> dims;
  const std::vector<double> x = f.read("/membrane/positions", &dims);
  const auto nodes =
      static_cast<std::uint64_t>(c.cells) * static_cast<std::uint64_t>(c.nodes_per_cell);
  if (dims.size() != 2 || dims[0] != nodes || dims[1] != 3)
    throw InputError(fmt::format("{}: /membrane/positions: expected {} x 3 values", path, nodes));
  c.positions = Eigen::Map<const Points>(x.data(), 3, static_cast<Eigen::Index>(nodes));
  c.rows = f.read("/membrane/samples");
  const std::size_t width = row_width(c.cells);
  if (c.rows.empty() || c.rows.size() % width != 0)
    throw InputError(fmt::format("{}: /membrane/samples: expected rows of {} values", path, width));
  return c;
}

struct Part {
  std::string path;
  RunCheckpoint c;
};

/// The parts must be of one step with the same sample steps and claim no cell twice.
void check_parts_agree(std::vector<Part>& parts) {
  std::sort(parts.begin(), parts.end(),
            [](const Part& a, const Part& b) { return a.c.first_cell < b.c.first_cell; });
  const Part& p0 = parts.front();
  const std::size_t rows0 = p0.c.rows.size() / row_width(p0.c.cells);
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const Part &p = parts[i], &before = parts[i - 1];
    if (p.c.step != p0.c.step)
      throw InputError(fmt::format("{}: /membrane step is {}, {} is at step {}", p.path, p.c.step,
                                   p0.path, p0.c.step));
    if (p.c.first_cell < before.c.first_cell + before.c.cells)
      throw InputError(fmt::format("{}: /membrane first_cell {}: cell {} is claimed by {} too",
                                   p.path, p.c.first_cell, p.c.first_cell, before.path));
    const std::size_t rows = p.c.rows.size() / row_width(p.c.cells);
    bool same_steps = rows == rows0;
    for (std::size_t r = 0; same_steps && r < rows; ++r)
      same_steps = p.c.rows[r * row_width(p.c.cells)] == p0.c.rows[r * row_width(p0.c.cells)];
    if (!same_steps)
      throw InputError(
          fmt::format("{}: /membrane/samples: not the sample steps of {}", p.path, p0.path));
  }
}

const Part& part_holding(const std::vector<Part>& parts, int cell) {
  for (const Part& p : parts)
    if (cell >= p.c.first_cell && cell < p.c.first_cell + p.c.cells) return p;
  std::string held;
  for (const Part& p : parts)
    held +=
        fmt::format(" {} (cells {} to {})", p.path, p.c.first_cell, p.c.first_cell + p.c.cells - 1);
  throw InputError(fmt::format("--resume: no checkpoint holds cell {}:{}", cell, held));
}

}  // namespace

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

RunCheckpoint read_run_checkpoints(const std::vector<std::string>& paths,
                                   const RunCheckpoint& expected) {
  if (paths.empty()) throw InputError("--resume: no checkpoint given");
  std::vector<Part> parts;
  parts.reserve(paths.size());
  for (const std::string& path : paths) parts.push_back({path, read_part(path, expected)});
  check_parts_agree(parts);
  RunCheckpoint c = expected;
  c.step = parts.front().c.step;
  const Eigen::Index n = expected.nodes_per_cell;
  c.positions.resize(3, n * expected.cells);
  const std::size_t rows = parts.front().c.rows.size() / row_width(parts.front().c.cells);
  const std::size_t width = row_width(expected.cells);
  c.rows.assign(rows * width, 0.0);
  for (std::size_t r = 0; r < rows; ++r)
    c.rows[r * width] = parts.front().c.rows[r * row_width(parts.front().c.cells)];
  for (int k = 0; k < expected.cells; ++k) {
    const int cell = expected.first_cell + k;
    const Part& p = part_holding(parts, cell);
    const int local = cell - p.c.first_cell;
    c.positions.middleCols(k * n, n) = p.c.positions.middleCols(local * n, n);
    const std::size_t from_width = row_width(p.c.cells);
    for (std::size_t r = 0; r < rows; ++r)
      std::copy_n(
          &p.c.rows[r * from_width + 1 + kSampleValuesPerCell * static_cast<std::size_t>(local)],
          kSampleValuesPerCell,
          &c.rows[r * width + 1 + kSampleValuesPerCell * static_cast<std::size_t>(k)]);
  }
  return c;
}

}  // namespace dld::membrane
