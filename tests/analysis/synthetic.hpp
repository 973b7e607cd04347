// SPDX-License-Identifier: MIT
// Synthetic cell paths and run files for the analysis tests (device frame, um).
#pragma once
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "analysis/run_file.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::analysis::testing {

constexpr double kLambda = 32.0;

/// A cell moving along x from (x0, y0) over `columns` columns in `samples` steps, y = y0 + f(c)
/// with c = (x - x0) / lambda the columns advanced.
inline CellTrack track(int id, double x0, double y0, double columns,
                       const std::function<double(double)>& f, int samples = 2000) {
  CellTrack t;
  t.id = id;
  for (int s = 0; s <= samples; ++s) {
    const double c = columns * s / samples;
    t.step.push_back(100.0 * s);
    t.position.push_back({x0 + c * kLambda, y0 + f(c), 2.4});
    t.volume.push_back(94.0);
  }
  return t;
}

/// A wiggle of amplitude a that is zero at every whole column: it must not change y(N).
inline double wiggle(double c, double a = 3.0) {
  return a * std::sin(2 * std::numbers::pi * c);
}

/// A smooth step from 0 to 1 in the middle of each column: 0 at whole columns, 1 after one.
inline double steps(double c) {
  const double frac = c - std::floor(c);
  return std::floor(c) + (frac < 0.4 ? 0.0 : frac > 0.6 ? 1.0 : (frac - 0.4) / 0.2);
}

struct FileFacts {
  int first_cell = 0;
  double lambda = kLambda, d = 4.4;
  std::string scene = "synthetic";
  double ca = 0.5;
  bool with_ca = true;
  std::string expected_mode = "";  ///< the scene's [cells] expected_mode; "" = no attribute
};

/// Writes tracks (same sample count) as dld-membrane does (membrane/coupled_main.cpp).
inline void write_run_file(const std::string& path, const std::vector<CellTrack>& cells,
                           const FileFacts& f) {
  H5File h(path, H5File::Mode::kCreate);
  const std::size_t width = 1 + 4 * cells.size();
  std::vector<double> rows;
  for (std::size_t i = 0; i < cells.front().step.size(); ++i) {
    rows.push_back(cells.front().step[i]);
    for (const auto& c : cells) {
      rows.insert(rows.end(), {c.position[i][0], c.position[i][1], c.position[i][2], c.volume[i]});
    }
  }
  h.write("/cells/samples", rows.data(), {rows.size() / width, width});
  h.attribute("/cells", "count", static_cast<std::int64_t>(cells.size()));
  h.attribute("/cells", "first_cell", static_cast<std::int64_t>(f.first_cell));
  h.attribute("/cells", "dt_s", 1e-7);
  h.attribute("/cells", "frame", std::string("device"));
  h.attribute("/cells", "pillar_spacing_um", f.lambda);
  h.attribute("/cells", "row_shift_um", f.d);
  h.attribute("/cells", "scene_name", f.scene);
  if (f.with_ca) {
    h.attribute("/cells", "capillary_number", f.ca);
  }
  if (!f.expected_mode.empty()) {
    h.attribute("/cells", "expected_mode", f.expected_mode);
  }
}

/// The run file dld-run writes from part files (coupler/launcher/run_file_merge, whose own test
/// checks that layout against the parts): part k's root as /membrane-k, and the root attribute
/// membrane_processes (`stated`; -1 leaves it out).
inline void write_merged_run_file(const std::string& path, const std::vector<std::string>& parts,
                                  std::int64_t stated) {
  H5File out(path, H5File::Mode::kCreate);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    out.copy_from(H5File(parts[k], H5File::Mode::kRead), "/", "/membrane-" + std::to_string(k));
  }
  if (stated >= 0) {
    out.attribute("/", "membrane_processes", stated);
  }
}

/// The InputError message of f(), or "" if it does not throw one.
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A fresh directory under the system temporary directory for one test.
std::string temp_dir(const std::string& name);

}  // namespace dld::analysis::testing
