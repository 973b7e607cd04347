// SPDX-License-Identifier: MIT
// The run file of a fluid run: one HDF5 file with the resolved scene, a time series, field
// snapshots (physical units) and results, plus an XDMF side file so ParaView opens the fields.
// The file is flushed after every write, so an interrupted run keeps what it had written.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "shared/h5file.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

/// Columns of a /timeseries row (see FluidRunFile::sample).
inline constexpr std::size_t kTimeseriesColumns = 8;

class FluidRunFile {
 public:
  /// A new run file; `timeseries`: rows to start /timeseries with (those of a resumed run, from
  /// its checkpoint).
  FluidRunFile(const Scene& scene, const std::string& path,
               const std::vector<double>& timeseries = {});

  /// One row of /timeseries: step, time [s], mean u (x, y, z) [m/s], mass [lattice], gap flux
  /// [m^3/s], lateral force [Pa/m].
  void sample(const FluidSolver& solver, double gap_flux_m3_s);
  /// Velocity [m/s], density [kg/m^3] and the solid mask at the current step.
  void snapshot(const FluidSolver& solver);
  /// A named scalar result under /results, with its unit.
  void result(const std::string& name, double value, const std::string& unit);
  void result_array(const std::string& name, const std::vector<double>& values);
  const std::string& path() const { return file_.path(); }
  /// Every /timeseries row written, row-major (kTimeseriesColumns each): kept with checkpoints.
  const std::vector<double>& timeseries() const { return timeseries_; }
  std::string xdmf_path() const;

 private:
  void write_xdmf() const;
  Scene scene_;
  LatticeUnits units_;
  H5File file_;
  std::vector<std::int64_t> snapshots_;
  std::vector<double> timeseries_;
  void append(const std::vector<double>& row);
};

}  // namespace dld::fluid
