// SPDX-License-Identifier: MIT
#include "analysis/run_file.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <regex>

#include "analysis/expected_mode.hpp"
#include "analysis/unwrap.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::analysis {

std::string run_stem(const std::string& path) {
  static const std::regex cells(R"((.*)-cells-[0-9]+\.h5$)");
  std::smatch m;
  if (std::regex_match(path, m, cells)) {
    return m[1].str();
  }
  return path.size() > 3 && path.ends_with(".h5") ? path.substr(0, path.size() - 3) : path;
}

namespace {

/// The cells of one membrane process: `group` is "/cells" in its part file, "/membrane-k/cells"
/// in the run file dld-run merges.
Run read_cells_group(const H5File& f, const std::string& path, const std::string& group) {
  Run r;
  r.stem = run_stem(path);
  r.files = {path};
  auto number = [&](const char* name) { return f.read_attribute_number(group, name); };
  if (!f.exists(group + "/samples")) {
    throw InputError(
        fmt::format("{}: no dataset {}/samples (is this a dld-membrane run file?)", path, group));
  }
  const auto count = number("count");
  const auto first = number("first_cell");
  if (count < 1 || first < 0 || count != std::floor(count) || first != std::floor(first)) {
    throw InputError(fmt::format(
        "{}: {} attributes count = {} and first_cell = {}: expected whole numbers, count >= 1",
        path, group, count, first));
  }
  r.dt_s = number("dt_s");
  r.lambda_um = number("pillar_spacing_um");
  r.row_shift_um = number("row_shift_um");
  if (!(r.lambda_um > 0) || !(r.row_shift_um >= 0) || !(r.row_shift_um < r.lambda_um)) {
    throw InputError(
        fmt::format("{}: {} pillar_spacing_um = {}, row_shift_um = {}: expected 0 <= d < lambda",
                    path, group, r.lambda_um, r.row_shift_um));
  }
  const auto frame = f.read_attribute_string(group, "frame");
  if (frame != "device" && frame != "box") {
    throw InputError(
        fmt::format("{}: {} frame = '{}': expected 'device' (or 'box')", path, group, frame));
  }
  r.scene_name = f.read_attribute_string(group, "scene_name");
  try {
    r.capillary_number = number("capillary_number");
  } catch (const InputError&) {  // optional: scenes without a capillary number
  }
  // Optional too (scenes that leave it to the dilute-limit map), but a value that is there must be
  // a mode: a typo must not quietly hand the run to the map.
  if (f.has_attribute(group, "expected_mode")) {
    r.expected_mode = parse_expected_mode(f.read_attribute_string(group, "expected_mode"),
                                          path + ": " + group + " expected_mode");
  }

  std::vector<std::uint64_t> dims;
  const std::vector<double> rows = f.read(group + "/samples", &dims);
  const auto cells = static_cast<std::size_t>(count);
  const std::size_t width = 1 + 4 * cells;
  if (dims.size() != 2 || dims[1] != width || dims[0] < 1) {
    throw InputError(fmt::format(
        "{}: {}/samples has shape ({}): expected (rows >= 1, {}) for {} cells (step, then x y z "
        "volume per cell)",
        path, group, fmt::join(dims, ", "), width, cells));
  }
  for (std::size_t k = 0; k < cells; ++k) {
    CellTrack t;
    t.id = static_cast<int>(first) + static_cast<int>(k);
    for (std::size_t i = 0; i < dims[0]; ++i) {
      const double* v = &rows[i * width];
      t.step.push_back(v[0]);
      t.position.push_back({v[1 + 4 * k], v[2 + 4 * k], v[3 + 4 * k]});
      t.volume.push_back(v[4 + 4 * k]);
      if (!std::isfinite(v[1 + 4 * k]) || !std::isfinite(v[2 + 4 * k])) {
        throw InputError(fmt::format("{}: {}/samples row {}: cell {} has a non-finite centroid",
                                     path, group, i, t.id));
      }
    }
    if (frame == "box") {  // folded into the unit cell: back to device coordinates (SPEC 7)
      t.position =
          unwrap_box_trajectory(DldCell{r.lambda_um, 0.0, 0.0, r.row_shift_um}, t.position);
    }
    r.cells.push_back(std::move(t));
  }
  return r;
}

/// "membrane-3" -> 3; -1 for any other name.
int membrane_index(const std::string& name) {
  static const std::regex pattern(R"(membrane-([0-9]+))");
  std::smatch m;
  return std::regex_match(name, m, pattern) ? std::stoi(m[1].str()) : -1;
}

/// The run file dld-run merges: /membrane-k/cells for k < membrane_processes (the root
/// attribute), merged as their part files would be.
Run read_merged_file(const H5File& f, const std::string& path) {
  std::vector<std::string> groups;
  for (const std::string& m : f.members("/")) {
    if (membrane_index(m) >= 0 && f.exists("/" + m + "/cells")) {
      groups.push_back("/" + m + "/cells");
    }
  }
  if (groups.empty()) {
    throw InputError(fmt::format(
        "{}: no dataset /cells/samples and no /membrane-K/cells group: expected a dld-membrane "
        "run file <stem>-cells-K.h5 or the run file <stem>.h5 of dld-run --membrane cells",
        path));
  }
  // A group lost on the way (a file put together by hand) would silently drop cells.
  if (f.has_attribute("/", "membrane_processes")) {
    const double expected = f.read_attribute_number("/", "membrane_processes");
    if (static_cast<double>(groups.size()) != expected) {
      throw InputError(
          fmt::format("{}: {} /membrane-K/cells groups: expected {} (attribute "
                      "membrane_processes)",
                      path, groups.size(), expected));
    }
  }
  std::vector<Run> parts;
  for (const std::string& g : groups) {
    parts.push_back(read_cells_group(f, path, g));
    // merge_runs names the parts by their files: here the group says which part disagrees.
    parts.back().files = {path};
    parts.back().files.back().append(" ").append(g);
  }
  Run r = merge_runs(std::move(parts));
  r.files = {path};
  return r;
}

}  // namespace

Run read_run_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(fmt::format(
        "{}: no such file (expected a dld-membrane run file or the run file of dld-run)", path));
  }
  const H5File f(path, H5File::Mode::kRead);
  return f.exists("/cells") ? read_cells_group(f, path, "/cells") : read_merged_file(f, path);
}

Run merge_runs(std::vector<Run> parts) {
  if (parts.empty()) {
    throw InputError("no run file given");
  }
  Run out = std::move(parts.front());
  for (std::size_t p = 1; p < parts.size(); ++p) {
    Run& r = parts[p];
    const auto mismatch = [&](const char* what, const auto& a, const auto& b) {
      return InputError(fmt::format("{}: {} = {} but {} has {}: expected the files of one run",
                                    r.files.front(), what, b, out.files.front(), a));
    };
    if (r.stem != out.stem) {
      throw mismatch("run name", out.stem, r.stem);
    }
    if (r.scene_name != out.scene_name) {
      throw mismatch("scene_name", out.scene_name, r.scene_name);
    }
    if (r.lambda_um != out.lambda_um) {
      throw mismatch("pillar_spacing_um", out.lambda_um, r.lambda_um);
    }
    if (r.row_shift_um != out.row_shift_um) {
      throw mismatch("row_shift_um", out.row_shift_um, r.row_shift_um);
    }
    if (r.capillary_number != out.capillary_number) {
      throw mismatch("capillary_number", out.capillary_number.value_or(NAN),
                     r.capillary_number.value_or(NAN));
    }
    if (r.expected_mode != out.expected_mode) {
      const auto name = [](const std::optional<TransportMode>& m) {
        return m ? to_string(*m) : std::string("(none)");
      };
      throw mismatch("expected_mode", name(out.expected_mode), name(r.expected_mode));
    }
    for (const CellTrack& t : r.cells) {
      for (const CellTrack& o : out.cells) {
        if (t.id == o.id) {
          throw InputError(fmt::format("{}: cell {} is also in {}: expected each cell in one file",
                                       r.files.front(), t.id, out.files.front()));
        }
      }
    }
    out.files.insert(out.files.end(), r.files.begin(), r.files.end());
    std::move(r.cells.begin(), r.cells.end(), std::back_inserter(out.cells));
  }
  std::sort(out.cells.begin(), out.cells.end(),
            [](const CellTrack& a, const CellTrack& b) { return a.id < b.id; });
  return out;
}

Run read_run(const std::vector<std::string>& paths) {
  std::vector<Run> parts;
  std::vector<std::string> skipped;
  parts.reserve(paths.size());
  for (const auto& p : paths) {
    if (p.ends_with(".ckpt.h5")) {
      skipped.push_back(p);
    } else {
      parts.push_back(read_run_file(p));
    }
  }
  if (parts.empty() && !skipped.empty()) {
    throw InputError(fmt::format("{}: a checkpoint, not a run file: expected <stem>-cells-K.h5",
                                 skipped.front()));
  }
  Run r = merge_runs(std::move(parts));
  r.skipped = std::move(skipped);
  return r;
}

}  // namespace dld::analysis
