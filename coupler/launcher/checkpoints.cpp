// SPDX-License-Identifier: MIT
#include "coupler/launcher/checkpoints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <optional>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

namespace fs = std::filesystem;

std::int64_t checkpoint_step(const std::string& path, const std::string& group) {
  if (!fs::exists(path)) {
    return -1;
  }
  try {
    return static_cast<std::int64_t>(
        dld::H5File(path, dld::H5File::Mode::kRead).read_attribute_number(group, "step"));
  } catch (const dld::InputError&) {
    return -1;
  }
}

namespace {

/// A membrane checkpoint's step and cells [first, first + cells).
struct CellsPart {
  std::string path;
  std::int64_t step = -1;
  int first = 0, cells = 0;
};

std::optional<CellsPart> read_cells_part(const std::string& path) {
  if (!fs::exists(path)) return std::nullopt;
  try {
    const dld::H5File f(path, dld::H5File::Mode::kRead);
    return CellsPart{path, static_cast<std::int64_t>(f.read_attribute_number("/membrane", "step")),
                     static_cast<int>(f.read_attribute_number("/membrane", "first_cell")),
                     static_cast<int>(f.read_attribute_number("/membrane", "cells"))};
  } catch (const dld::InputError&) {
    return CellsPart{path, -1, 0, 0};  // unreadable: named in the error if nothing else fits
  }
}

/// Parts of `step` that hold cells [from, total) each once (depth first: two splits that wrote the
/// same step both hold the whole state, bit for bit the same, so any tiling will do).
bool tile(const std::vector<CellsPart>& parts, std::int64_t step, int from, int total,
          std::vector<std::string>& chosen) {
  if (from == total) return true;
  for (const CellsPart& p : parts) {
    if (p.step != step || p.first != from || p.cells < 1 || p.first + p.cells > total) continue;
    chosen.push_back(p.path);
    if (tile(parts, step, from + p.cells, total, chosen)) return true;
    chosen.pop_back();
  }
  return false;
}

std::string describe(const std::string& path, std::int64_t step) {
  return fmt::format(" {} ({})", path,
                     step >= 0           ? fmt::format("step {}", step)
                     : !fs::exists(path) ? std::string("no such file")
                                         : std::string("not a readable checkpoint"));
}

}  // namespace

ResumePoint coupled_resume_point(const std::string& fluid,
                                 const std::vector<std::string>& membrane_files, int total_cells,
                                 std::size_t expected_files) {
  std::vector<CellsPart> parts;
  std::string missing;  // the files this run's processes write, for the error
  for (std::size_t k = 0; k < membrane_files.size(); ++k) {
    const std::string& file = membrane_files[k];
    if (auto part = read_cells_part(file))
      parts.push_back(*part);
    else if (k < expected_files)
      missing += describe(file, -1);
    if (auto part = read_cells_part(file + ".prev")) parts.push_back(*part);
  }
  for (const std::string& f : {fluid, fluid + ".prev"}) {
    const std::int64_t step = checkpoint_step(f, "/fluid");
    if (step < 0) continue;
    ResumePoint r{step, f, {}};
    if (tile(parts, step, 0, total_cells, r.cells)) return r;
  }
  // Each file and why it cannot be used: a corrupt file is not a missing one.
  std::string found = describe(fluid, checkpoint_step(fluid, "/fluid"));
  found += describe(fluid + ".prev", checkpoint_step(fluid + ".prev", "/fluid"));
  for (const CellsPart& p : parts)
    found += p.step < 0 ? describe(p.path, -1)
                        : fmt::format(" {} (step {}, cells {} to {})", p.path, p.step, p.first,
                                      p.first + p.cells - 1);
  found += missing;
  throw dld::InputError(fmt::format(
      "--resume: no step at which the fluid's checkpoint and membrane checkpoints holding all {} "
      "cells meet:{}",
      total_cells, found));
}

}  // namespace dld::coupler
