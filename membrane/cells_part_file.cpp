// SPDX-License-Identifier: MIT
#include "membrane/cells_part_file.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>

#include "membrane/mesh_output.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

std::string make_file(const std::string& path, const RunFacts& r, const std::vector<double>& rows,
                      std::optional<std::int64_t> resumed_at) {
  std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  const std::string tmp = path + ".tmp";
  {
    H5File f(tmp, H5File::Mode::kCreate);
    const std::uint64_t width = 1 + 4 * static_cast<std::uint64_t>(r.cells);
    f.append("/cells/samples", rows.data(), rows.size() / width, {width});
    f.attribute(
        "/cells/samples", "columns",
        std::string("step, then per cell: centroid x y z [um, device frame], volume [um^3]"));
    f.attribute("/cells", "count", static_cast<std::int64_t>(r.cells));
    f.attribute("/cells", "first_cell", static_cast<std::int64_t>(r.first_cell));
    f.attribute("/cells", "dt_s", r.dt_s);
    f.attribute("/cells", "frame", std::string("device"));
    f.attribute("/cells", "pillar_spacing_um", r.lambda_um);
    f.attribute("/cells", "row_shift_um", r.row_shift_um);
    f.attribute("/cells", "scene_name", r.scene_name);
    if (r.capillary_number) f.attribute("/cells", "capillary_number", *r.capillary_number);
    // Only when stated: without it dld-analyze falls back to its dilute-limit map.
    if (r.expected_mode) f.attribute("/cells", "expected_mode", to_string(*r.expected_mode));
    if (resumed_at && std::filesystem::exists(path)) {
      // The meshes are not in the checkpoint (too large): they come from the previous part file.
      try {
        const H5File old(path, H5File::Mode::kRead);
        // A run resumed with another split: the previous part held other cells.
        const bool same_cells = old.read_attribute_number("/cells", "first_cell") == r.first_cell &&
                                old.read_attribute_number("/cells", "count") == r.cells;
        if (old.exists("/cells/mesh") && !same_cells) {
          spdlog::warn(
              "the meshes before step {} are not carried over: the previous part file {} holds "
              "other cells (the run was split over another number of membrane processes)",
              *resumed_at, path);
        } else if (old.exists("/cells/mesh")) {
          f.copy_from(old, "/cells/mesh", "/cells/mesh");
          keep_mesh_samples_until(f, *resumed_at);
        }
      } catch (const InputError& e) {
        spdlog::warn("the meshes before step {} are lost: {}", *resumed_at, e.what());
      }
    }
    f.close();
  }
  std::filesystem::rename(tmp, path);
  return path;
}

}  // namespace

CellsPartFile::CellsPartFile(const std::string& path, const RunFacts& facts,
                             const std::vector<double>& rows,
                             std::optional<std::int64_t> resumed_at)
    : width_(1 + 4 * static_cast<std::size_t>(facts.cells)),
      file_(make_file(path, facts, rows, resumed_at), H5File::Mode::kReadWrite) {}

void CellsPartFile::append(const std::vector<double>& row) {
  if (row.size() != width_)
    throw InputError(fmt::format("{}: a sample row of {} values, expected {}", file_.path(),
                                 row.size(), width_));
  file_.append("/cells/samples", row.data(), 1, {width_});
  file_.flush();
}

}  // namespace dld::membrane
