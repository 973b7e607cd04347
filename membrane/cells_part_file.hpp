// SPDX-License-Identifier: MIT
// The part file of one coupled membrane process (<run>-cells-k.h5, docs/architecture.md "The run
// file"): /cells/samples, one row per sample (step, then per cell centroid x y z [um, device
// frame] and volume [um^3]), the run's facts as /cells attributes (read by dld-analyze), and
// /cells/mesh when the scene asks for meshes (membrane/mesh_output).
// The file stays open and is flushed after every appended row, so a crash loses at most the row
// being written; the meshes need this, since rewriting them whole at every flush would cost as
// much as they weigh. It is made through a temporary file and a rename: a resumed run's previous
// part stays whole until the new one, which starts from the checkpoint's samples, is.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "shared/column_tracker.hpp"
#include "shared/h5file.hpp"

namespace dld::membrane {

/// What a run file says about the run besides the samples (read by dld-analyze).
struct RunFacts {
  int cells = 0, first_cell = 0;
  double dt_s = 0, lambda_um = 0, row_shift_um = 0;
  std::string scene_name;
  std::optional<double> capillary_number;
  std::optional<TransportMode> expected_mode;  ///< the scene's [cells] expected_mode, if stated
};

class CellsPartFile {
 public:
  /// Creates `path` with `facts` and the samples `rows` so far (row-major, 1 + 4 cells wide: a
  /// resumed run's, from its checkpoint). `resumed_at`: the checkpoint's step; the mesh samples of
  /// the previous part file up to it are kept (the later ones come again).
  CellsPartFile(const std::string& path, const RunFacts& facts, const std::vector<double>& rows,
                std::optional<std::int64_t> resumed_at);
  /// Appends one sample row and flushes.
  void append(const std::vector<double>& row);
  H5File& file() { return file_; }

 private:
  std::size_t width_;
  H5File file_;
};

}  // namespace dld::membrane
