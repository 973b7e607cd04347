// SPDX-License-Identifier: MIT
// The cells run files written by dld-membrane (`<stem>-cells-K.h5`, one per membrane process):
// /cells/samples rows = step, then per cell centroid x y z [um, device frame, unwrapped] and
// volume [um^3]; attributes on /cells name the run's geometry. The files of one run are merged by
// their first_cell attribute. The run file `dld-run` writes (`<stem>.h5`) holds each of them as
// /membrane-k (/membrane-k/cells, ...): one such file stands for all of them. A file with
// frame = "box" (centroids folded into the unit cell) is unwrapped into device coordinates on
// reading.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "shared/column_tracker.hpp"

namespace dld::analysis {

/// One cell's centroid path in device coordinates [um], one entry per saved sample.
struct CellTrack {
  int id = 0;  ///< global cell index (first_cell of its file + column)
  std::vector<double> step;
  std::vector<std::array<double, 3>> position;  ///< [um, device frame]
  std::vector<double> volume;                   ///< [um^3]
};

struct Run {
  std::string stem;  ///< input path without "-cells-K.h5" (names the outputs)
  std::string scene_name;
  double lambda_um = 0;     ///< pillar spacing lambda
  double row_shift_um = 0;  ///< row shift d
  double dt_s = 0;
  std::optional<double> capillary_number;
  /// The scene's [cells] expected_mode (attribute expected_mode): kZigzag or kDisplacement.
  std::optional<TransportMode> expected_mode;
  std::vector<std::string> files;
  std::vector<std::string> skipped;  ///< checkpoint files among the inputs (not read)
  std::vector<CellTrack> cells;      ///< ordered by id
};

/// `dir/name-cells-3.h5` -> `dir/name`; a path without that ending loses only ".h5".
std::string run_stem(const std::string& path);

/// Reads one cells run file, or every /membrane-k/cells group of the run file dld-run merges (all
/// of them must be there: root attribute membrane_processes); any missing or malformed part is an
/// InputError naming the file and what was expected.
Run read_run_file(const std::string& path);

/// Merges the files of one run (same stem, geometry and scene; cells must not repeat).
Run merge_runs(std::vector<Run> parts);

/// read_run_file on each path, then merge_runs. Checkpoints (`*.ckpt.h5`, which the shell glob
/// `<stem>-cells-*.h5` also matches) are skipped and listed in `skipped`.
Run read_run(const std::vector<std::string>& paths);

}  // namespace dld::analysis
