// SPDX-License-Identifier: MIT
// The run file of a fluid run: one HDF5 file with the resolved scene, a time series, field
// snapshots (physical units) and results, plus an XDMF side file so ParaView opens the fields.
// The file is flushed after every write, so an interrupted run keeps what it had written.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "shared/h5file.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

class FluidRunFile {
 public:
  FluidRunFile(const Scene& scene, const std::string& path);

  /// One row of /timeseries: step, time [s], mean u (x, y, z) [m/s], mass [lattice], gap flux
  /// [m^3/s], lateral force [Pa/m].
  void sample(const FluidSolver& solver, double gap_flux_m3_s);
  /// Velocity [m/s], density [kg/m^3] and the solid mask at the current step.
  void snapshot(const FluidSolver& solver);
  /// A named scalar result under /results, with its unit.
  void result(const std::string& name, double value, const std::string& unit);
  void result_array(const std::string& name, const std::vector<double>& values);
  const std::string& path() const { return file_.path(); }
  std::string xdmf_path() const;

 private:
  void write_xdmf() const;
  Scene scene_;
  LatticeUnits units_;
  H5File file_;
  std::vector<std::int64_t> snapshots_;
};

}  // namespace dld::fluid
