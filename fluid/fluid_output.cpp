// SPDX-License-Identifier: MIT
#include "fluid/fluid_output.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <fstream>

namespace dld::fluid {
namespace {
H5File create_file(const std::string& path) {
  std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  return H5File(path, H5File::Mode::kCreate);
}
}  // namespace

FluidRunFile::FluidRunFile(const Scene& scene, const std::string& path,
                           const std::vector<double>& timeseries)
    : scene_(scene), units_(scene.units()), file_(create_file(path)) {
  file_.attribute("/", "program", std::string("dld-fluid"));
  file_.attribute("/", "scene_name", scene.name);
  file_.attribute("/", "scene_file", scene.file);
  file_.attribute("/", "resolved_scene", scene.describe());
  const std::string s = "/scene";
  file_.attribute(s, "lambda_um", scene.cell_um.lambda);
  file_.attribute(s, "pillar_radius_um", scene.cell_um.radius);
  file_.attribute(s, "depth_um", scene.cell_um.depth);
  file_.attribute(s, "row_shift_um", scene.cell_um.shift);
  file_.attribute(s, "dx_m", units_.dx_m());
  file_.attribute(s, "dt_s", units_.dt_s());
  file_.attribute(s, "density_kg_m3", scene.fluid.density_kg_m3);
  file_.attribute(s, "viscosity_Pa_s", scene.fluid.viscosity_Pa_s);
  file_.attribute(s, "tau", scene.lattice.tau);
  file_.attribute(s, "pressure_gradient_Pa_per_m", scene.drive.pressure_gradient_Pa_per_m);
  file_.attribute(s, "nx", static_cast<std::int64_t>(scene.nx()));
  file_.attribute(s, "ny", static_cast<std::int64_t>(scene.ny()));
  file_.attribute(s, "nz", static_cast<std::int64_t>(scene.nz()));
  for (std::size_t r = 0; r + kTimeseriesColumns <= timeseries.size(); r += kTimeseriesColumns)
    append(std::vector<double>(
        timeseries.begin() + static_cast<std::ptrdiff_t>(r),
        timeseries.begin() + static_cast<std::ptrdiff_t>(r + kTimeseriesColumns)));
  file_.flush();
}

void FluidRunFile::append(const std::vector<double>& row) {
  file_.append_row("/timeseries", row,
                   {"step", "time_s", "mean_ux_m_s", "mean_uy_m_s", "mean_uz_m_s", "mass_lu",
                    "gap_flux_m3_s", "force_y_Pa_per_m"});
  timeseries_.insert(timeseries_.end(), row.begin(), row.end());
}

void FluidRunFile::sample(const FluidSolver& solver, double gap_flux_m3_s) {
  const auto u = solver.mean_velocity();
  append({static_cast<double>(solver.steps()), units_.time_s(solver.steps()),
          units_.velocity_m_s(u[0]), units_.velocity_m_s(u[1]), units_.velocity_m_s(u[2]),
          solver.total_mass(), gap_flux_m3_s, units_.force_density_n_m3(solver.force_y())});
  file_.flush();
}

void FluidRunFile::snapshot(const FluidSolver& solver) {
  // A run that ends on a snapshot step asks twice: one grid per step (a second one, written over
  // the first, read empty in ParaView).
  if (!snapshots_.empty() && snapshots_.back() == solver.steps()) return;
  std::vector<double> rho, ux, uy, uz;
  solver.fields(rho, ux, uy, uz);
  const std::size_t n = rho.size();
  std::vector<double> vel(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    vel[3 * i] = units_.velocity_m_s(ux[i]);
    vel[3 * i + 1] = units_.velocity_m_s(uy[i]);
    vel[3 * i + 2] = units_.velocity_m_s(uz[i]);
    rho[i] *= units_.rho_kg_m3();
  }
  const auto& L = solver.lattice();
  const std::uint64_t nz = L.nz(), ny = L.ny(), nx = L.nx();
  const std::string g = fmt::format("/fields/step_{:09d}", solver.steps());
  file_.write(g + "/velocity_m_s", vel.data(), {nz, ny, nx, 3});
  file_.write(g + "/density_kg_m3", rho.data(), {nz, ny, nx});
  file_.attribute(g, "step", static_cast<std::int64_t>(solver.steps()));
  file_.attribute(g, "time_s", units_.time_s(solver.steps()));
  if (!file_.exists("/fields/solid")) {
    std::vector<std::int32_t> solid(n);
    for (int k = 0; k < L.nz(); ++k)
      for (int j = 0; j < L.ny(); ++j)
        for (int i = 0; i < L.nx(); ++i)
          solid[(static_cast<std::size_t>(k) * ny + j) * nx + i] = L.solid(i, j, k) ? 1 : 0;
    file_.write("/fields/solid", solid.data(), {nz, ny, nx});
  }
  file_.flush();
  snapshots_.push_back(solver.steps());
  write_xdmf();
}

void FluidRunFile::result(const std::string& name, double value, const std::string& unit) {
  file_.write("/results/" + name, std::vector<double>{value});
  file_.attribute("/results/" + name, "unit", unit);
  file_.flush();
}

void FluidRunFile::result_array(const std::string& name, const std::vector<double>& values) {
  file_.write("/results/" + name, values);
  file_.flush();
}

std::string FluidRunFile::xdmf_path() const {
  std::filesystem::path p(file_.path());
  return p.replace_extension(".xmf").string();
}

void FluidRunFile::write_xdmf() const {
  // Cell-centred values on a co-rectilinear grid of nodes (um), one grid per snapshot.
  const int nx = scene_.nx(), ny = scene_.ny(), nz = scene_.nz();
  const double dx = scene_.lattice.dx_um;
  const std::string h5 = std::filesystem::path(file_.path()).filename().string();
  const std::string tmp = xdmf_path() + ".tmp";
  {
    std::ofstream x(tmp);
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "<Grid Name=\"fluid\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (std::int64_t step : snapshots_) {
      const std::string g = fmt::format("/fields/step_{:09d}", step);
      x << fmt::format("<Grid Name=\"step {}\" GridType=\"Uniform\">\n", step)
        << fmt::format("<Time Value=\"{}\"/>\n", units_.time_s(step))
        << fmt::format("<Topology TopologyType=\"3DCoRectMesh\" Dimensions=\"{} {} {}\"/>\n", nz,
                       ny, nx)
        << "<Geometry GeometryType=\"ORIGIN_DXDYDZ\">\n"
        << fmt::format("<DataItem Dimensions=\"3\" Format=\"XML\">{} {} {}</DataItem>\n", 0.5 * dx,
                       0.5 * dx, 0.5 * dx)
        << fmt::format("<DataItem Dimensions=\"3\" Format=\"XML\">{} {} {}</DataItem>\n", dx, dx,
                       dx)
        << "</Geometry>\n"
        << "<Attribute Name=\"velocity_m_s\" AttributeType=\"Vector\" Center=\"Node\">\n"
        << fmt::format(
               "<DataItem Dimensions=\"{} {} {} 3\" NumberType=\"Float\" Precision=\"8\" "
               "Format=\"HDF\">{}:{}/velocity_m_s</DataItem>\n</Attribute>\n",
               nz, ny, nx, h5, g)
        << "<Attribute Name=\"density_kg_m3\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        << fmt::format(
               "<DataItem Dimensions=\"{} {} {}\" NumberType=\"Float\" Precision=\"8\" "
               "Format=\"HDF\">{}:{}/density_kg_m3</DataItem>\n</Attribute>\n",
               nz, ny, nx, h5, g)
        << "<Attribute Name=\"solid\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        << fmt::format(
               "<DataItem Dimensions=\"{} {} {}\" NumberType=\"Int\" Precision=\"4\" "
               "Format=\"HDF\">{}:/fields/solid</DataItem>\n</Attribute>\n",
               nz, ny, nx, h5)
        << "</Grid>\n";
    }
    x << "</Grid>\n</Domain>\n</Xdmf>\n";
  }
  std::filesystem::rename(tmp, xdmf_path());
}

}  // namespace dld::fluid
