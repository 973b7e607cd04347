// SPDX-License-Identifier: MIT
// A fluid-only run of a scene: steps to steady state (or the step limit), samples the time
// series, writes snapshots and the separation-distance result. Used by dld-fluid and the tests.
#pragma once
#include <cstdint>
#include <string>

#include "shared/scene.hpp"

namespace dld::fluid {

struct FluidRunOptions {
  std::int64_t max_steps = -1;  ///< overrides scene.run.max_steps when >= 0
  std::string output;           ///< overrides scene.output.file when not empty
  bool write_file = true;
  bool progress = true;  ///< progress lines on the log
};

struct FluidRunSummary {
  std::int64_t steps = 0;
  bool steady = false;
  double mean_ux_m_s = 0, mean_uy_m_s = 0;
  double reynolds = 0;  ///< mean u_x G / nu
  double gap_flux_m3_s = 0;
  double separation_um = 0;  ///< band next to the pillar carrying eps = d/lambda of the gap flux
  double relative_mass_change = 0;  ///< |M(end) - M(0)| / M(0)
  double mlups = 0;                 ///< fluid-node updates per second (millions)
  double ms_per_step = 0;           ///< wall time of one step of the stepping loop [ms]
  std::string output;
};

FluidRunSummary run_fluid(const Scene& scene, const FluidRunOptions& options);

}  // namespace dld::fluid
