// SPDX-License-Identifier: MIT
#include "membrane/mesh_output.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const std::string kGroup = "/cells/mesh";
}  // namespace

std::string mesh_xdmf(const std::string& h5_name, std::int64_t nodes, std::int64_t faces,
                      const std::vector<MeshSample>& samples) {
  const std::string h5 = h5_name + ":" + kGroup;
  std::string x =
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      "<Grid Name=\"cells\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  const std::size_t s = samples.size();
  for (std::size_t i = 0; i < s; ++i) {
    // Every sample shares the faces; its nodes are sample/i, a view of slab i of positions (an
    // HDF5 virtual dataset: ParaView's default XDMF 3 reader reads no hyperslabs). Each grid names
    // its own data, so ParaView reads one sample at a time.
    x += fmt::format("<Grid Name=\"step {}\" GridType=\"Uniform\">\n", samples[i].step);
    x += fmt::format("<Time Value=\"{:.17g}\"/>\n", samples[i].time_s);
    x += fmt::format(
        "<Topology TopologyType=\"Triangle\" NumberOfElements=\"{0}\">\n"
        "<DataItem Dimensions=\"{0} 3\" NumberType=\"Int\" Precision=\"4\" "
        "Format=\"HDF\">{1}/faces</DataItem>\n</Topology>\n",
        faces, h5);
    x += fmt::format(
        "<Geometry GeometryType=\"XYZ\">\n"
        "<DataItem Dimensions=\"{0} 3\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{1}/sample/{2}</DataItem>\n</Geometry>\n",
        nodes, h5, i);
    x += fmt::format(
        "<Attribute Name=\"cell\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        "<DataItem Dimensions=\"{}\" NumberType=\"Int\" Precision=\"4\" "
        "Format=\"HDF\">{}/cell</DataItem>\n</Attribute>\n",
        nodes, h5);
    x += "</Grid>\n";
  }
  x += "</Grid>\n</Domain>\n</Xdmf>\n";
  return x;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw InputError(fmt::format("{}: cannot write", tmp));
  }
  std::filesystem::rename(tmp, path);
}

MeshOutput::MeshOutput(H5File& file, const TriMesh& reference, int cell_count, int first_cell,
                       double dt_s)
    : file_(file),
      nodes_(static_cast<std::int64_t>(cell_count) * reference.node_count()),
      faces_(static_cast<std::int64_t>(cell_count) * reference.face_count()),
      dt_s_(dt_s) {
  if (file_.exists(kGroup + "/faces")) {
    // A resumed run: the part file was made from the previous one and holds its samples (up to
    // the checkpoint's step). The scene is the same (checked against the checkpoint), so are the
    // faces.
    const auto steps = file_.read(kGroup + "/steps");
    const auto times = file_.read(kGroup + "/time_s");
    for (std::size_t i = 0; i < steps.size(); ++i) {
      samples_.push_back({static_cast<std::int64_t>(steps[i]), times[i]});
      const std::string view = kGroup + "/sample/" + std::to_string(i);
      if (!file_.exists(view)) file_.view_slab(view, kGroup + "/positions", i);  // older files
    }
    write_xdmf();  // the previous run's may name samples after the checkpoint
    return;
  }
  const int n = reference.node_count();
  std::vector<std::int32_t> faces, cell;
  faces.reserve(static_cast<std::size_t>(3 * faces_));
  for (int k = 0; k < cell_count; ++k) {
    for (const Face& f : reference.faces)
      for (int v : f) faces.push_back(static_cast<std::int32_t>(k * n + v));
    cell.insert(cell.end(), static_cast<std::size_t>(n), first_cell + k);
  }
  file_.write(kGroup + "/faces", faces.data(), {static_cast<std::uint64_t>(faces_), 3});
  file_.write(kGroup + "/cell", cell.data(), {static_cast<std::uint64_t>(nodes_)});
  // Empty, so that the layout is there from the start and a reader finds zero samples.
  file_.append(kGroup + "/positions", nullptr, 0, {static_cast<std::uint64_t>(nodes_), 3});
  file_.append(kGroup + "/steps", nullptr, 0, {});
  file_.append(kGroup + "/time_s", nullptr, 0, {});
  file_.attribute(kGroup, "frame", std::string("device"));
  file_.attribute(kGroup + "/positions", "unit", std::string("um"));
  file_.attribute(kGroup + "/positions", "meaning",
                  std::string("sample x node x (x, y, z); nodes of cell k (in this file's order) "
                              "are k n .. k n + n - 1, n = nodes per cell; unwrapped"));
  file_.attribute(kGroup, "nodes_per_cell", static_cast<std::int64_t>(n));
  file_.flush();
}

void MeshOutput::append(std::int64_t step, const Points& positions_um) {
  if (positions_um.cols() != nodes_)
    throw InputError(fmt::format("{}: a mesh sample of {} nodes, expected {}", file_.path(),
                                 positions_um.cols(), nodes_));
  // Eigen's 3 x N column-major layout is N x 3 row-major: x y z of node 0, then node 1, ...
  file_.append(kGroup + "/positions", positions_um.data(), 1,
               {static_cast<std::uint64_t>(nodes_), 3});
  file_.view_slab(kGroup + "/sample/" + std::to_string(samples_.size()), kGroup + "/positions",
                  samples_.size());
  const double s = static_cast<double>(step), t = static_cast<double>(step) * dt_s_;
  file_.append(kGroup + "/steps", &s, 1, {});
  file_.append(kGroup + "/time_s", &t, 1, {});
  file_.flush();
  samples_.push_back({step, t});
  // After the flush: the XDMF never names a sample the file does not hold yet.
  write_xdmf();
}

void MeshOutput::write_xdmf() const {
  write_text_atomically(
      xdmf_path(),
      mesh_xdmf(std::filesystem::path(file_.path()).filename().string(), nodes_, faces_, samples_));
}

std::string mesh_xdmf_path(const std::string& part_path) {
  return std::filesystem::path(part_path).replace_extension(".xmf").string();
}

void keep_mesh_samples_until(H5File& file, std::int64_t step) {
  if (!file.exists(kGroup + "/steps")) return;
  const auto steps = file.read(kGroup + "/steps");
  std::uint64_t keep = 0;
  while (keep < steps.size() && steps[keep] <= static_cast<double>(step)) ++keep;
  for (const char* d : {"/positions", "/steps", "/time_s"}) file.resize(kGroup + d, keep);
  for (std::uint64_t i = keep; i < steps.size(); ++i)
    file.remove(kGroup + "/sample/" + std::to_string(i));
}

}  // namespace dld::membrane
