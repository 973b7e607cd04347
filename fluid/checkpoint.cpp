// SPDX-License-Identifier: MIT
#include "fluid/checkpoint.hpp"

#include <fmt/format.h>

#include <filesystem>

#include "fluid/fluid_output.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::fluid {

void write_checkpoint(const std::string& path, const Scene& scene, const FluidSolver& solver,
                      const std::vector<double>& timeseries) {
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  const std::string tmp = path + ".tmp";
  {
    H5File f(tmp, H5File::Mode::kCreate);
    const std::size_t n = solver.lattice().padded_size() * D3Q19::q + kPopulationPadding;
    f.write("/fluid/populations", solver.pull_populations().data(), {n});
    // Which slots a restart takes from the file (1: interior fluid node; the others are refilled
    // before a step reads them), so that two programs' checkpoints can be compared where it
    // matters (bench/coupler/compare-builds).
    const Lattice& L = solver.lattice();
    std::vector<std::int32_t> fluid(L.padded_size(), 0);
    for (int k = 0; k < L.nz(); ++k)
      for (int j = 0; j < L.ny(); ++j)
        for (int i = 0; i < L.nx(); ++i) fluid[L.index(i, j, k)] = L.solid(i, j, k) ? 0 : 1;
    f.write("/fluid/fluid_nodes", fluid.data(), {fluid.size()});
    const FluidSolver::Memory m = solver.memory();
    f.attribute("/fluid", "step", static_cast<std::int64_t>(m.steps));
    f.attribute("/fluid", "force_y", m.force_y);
    f.attribute("/fluid", "applied_force_y", m.applied_force_y);
    f.attribute("/fluid", "controller_integral", m.controller_integral);
    f.attribute("/fluid", "mass", m.sums.mass);
    f.attribute("/fluid", "momentum_x", m.sums.momentum_x);
    f.attribute("/fluid", "momentum_y", m.sums.momentum_y);
    f.attribute("/fluid", "momentum_z", m.sums.momentum_z);
    f.attribute("/fluid", "scene_hash", scene.hash);
    f.attribute("/fluid", "lattice",
                fmt::format("{} x {} x {}", scene.nx(), scene.ny(), scene.nz()));
    if (!timeseries.empty())
      f.write("/fluid/timeseries", timeseries.data(),
              {timeseries.size() / kTimeseriesColumns, kTimeseriesColumns});
  }
  // Keep the previous checkpoint: if the other side of the run fails while writing its own, the
  // two still share a step to resume from.
  if (std::filesystem::exists(path)) std::filesystem::rename(path, path + ".prev");
  std::filesystem::rename(tmp, path);
}

std::int64_t read_checkpoint(const std::string& path, const Scene& scene, FluidSolver& solver,
                             std::vector<double>* timeseries) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: no such checkpoint", path));
  H5File f(path, H5File::Mode::kRead);
  const std::string hash = f.read_attribute_string("/fluid", "scene_hash");
  if (hash != scene.hash)
    throw InputError(fmt::format(
        "{}: /fluid scene_hash {} is not the scene's {} ({} was changed or is another scene)", path,
        hash, scene.hash, scene.file));
  std::vector<std::uint64_t> dims;
  std::vector<double> pops = f.read("/fluid/populations", &dims);
  const std::size_t n = solver.lattice().padded_size() * D3Q19::q + kPopulationPadding;
  if (pops.size() != n)
    throw InputError(fmt::format("{}: /fluid/populations has {} values, the lattice needs {}", path,
                                 pops.size(), n));
  FluidSolver::Memory m;
  m.steps = static_cast<std::int64_t>(f.read_attribute_number("/fluid", "step"));
  m.force_y = f.read_attribute_number("/fluid", "force_y");
  m.applied_force_y = f.read_attribute_number("/fluid", "applied_force_y");
  m.controller_integral = f.read_attribute_number("/fluid", "controller_integral");
  m.sums = {f.read_attribute_number("/fluid", "mass"),
            f.read_attribute_number("/fluid", "momentum_x"),
            f.read_attribute_number("/fluid", "momentum_y"),
            f.read_attribute_number("/fluid", "momentum_z")};
  solver.restore(pops, m);
  if (timeseries) {
    timeseries->clear();
    if (f.exists("/fluid/timeseries")) {
      std::vector<std::uint64_t> shape;
      *timeseries = f.read("/fluid/timeseries", &shape);
      if (shape.size() != 2 || shape[1] != kTimeseriesColumns)
        throw InputError(fmt::format("{}: /fluid/timeseries is not rows of {} columns", path,
                                     kTimeseriesColumns));
    }
  }
  return m.steps;
}

}  // namespace dld::fluid
