// SPDX-License-Identifier: MIT
// The cells' meshes over a coupled run, for ParaView ([output] mesh_every): every N steps the node
// positions of this process's cells (device frame, um, unwrapped like the samples) are appended to
// /cells/mesh in its part file, and an XDMF file beside it (<part>.xmf) describes them as a time
// series of triangle meshes. Layout (docs/architecture.md, "Output"):
//   /cells/mesh/faces      F x 3 int32, node indices over all cells of the file (cell k's nodes are
//                          k n .. k n + n - 1), written once
//   /cells/mesh/cell       N int32, the scene's index of each node's cell (to colour by cell)
//   /cells/mesh/positions  S x N x 3 [um], one slab per sample, extendible
//   /cells/mesh/sample/i   N x 3, a view of slab i of positions (HDF5 virtual dataset, no copy),
//                          what the XDMF names: ParaView's XDMF 3 reader takes whole datasets
//   /cells/mesh/steps, /cells/mesh/time_s   S, the step and time of each sample
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "membrane/mesh.hpp"
#include "shared/h5file.hpp"

namespace dld::membrane {

/// When a mesh sample was taken.
struct MeshSample {
  std::int64_t step = 0;
  double time_s = 0;
};

/// The XDMF 3 text for `samples` of a mesh of `nodes` nodes and `faces` triangles stored as above
/// in the HDF5 file `h5_name` (a name relative to the XDMF file: the two stay side by side).
std::string mesh_xdmf(const std::string& h5_name, std::int64_t nodes, std::int64_t faces,
                      const std::vector<MeshSample>& samples);

/// <part>.xmf: the part file's name with the extension .xmf.
std::string mesh_xdmf_path(const std::string& part_path);

/// Writes `text` to `path` through `path.tmp` and a rename, so a reader (or Ctrl-C, or a crash)
/// sees the previous whole file or the new one, never half of one.
void write_text_atomically(const std::string& path, const std::string& text);

class MeshOutput {
 public:
  /// Takes over /cells/mesh in `file` (which must outlive this): writes the faces of `cell_count`
  /// cells of the mesh `reference`, the first of them the scene's cell `first_cell`, unless the
  /// file holds them (a resumed run's part file, whose samples this picks up).
  MeshOutput(H5File& file, const TriMesh& reference, int cell_count, int first_cell, double dt_s);
  /// Appends the nodes `positions_um` (3 x N, um) as the sample of `step`, flushes the file and
  /// rewrites the XDMF.
  void append(std::int64_t step, const Points& positions_um);
  const std::vector<MeshSample>& samples() const { return samples_; }
  std::string xdmf_path() const { return mesh_xdmf_path(file_.path()); }

 private:
  void write_xdmf() const;
  H5File& file_;
  std::int64_t nodes_ = 0, faces_ = 0;
  double dt_s_ = 0;
  std::vector<MeshSample> samples_;
};

/// Keeps the mesh samples of `file` up to `step` and drops the later ones: a run resumed from a
/// checkpoint at `step` takes the samples after it again. Nothing when the file has no meshes.
void keep_mesh_samples_until(H5File& file, std::int64_t step);

}  // namespace dld::membrane
