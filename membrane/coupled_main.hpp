// SPDX-License-Identifier: MIT
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "coupler/tcp_security.hpp"
#include "membrane/membrane_scene.hpp"

namespace dld::membrane {

struct CoupledArgs {
  std::string endpoint;       ///< the fluid's base endpoint (dld-fluid --serve)
  int peer = 0, peers = 1;    ///< this process's index and the number of membrane processes
  std::int64_t steps = 1000;  ///< end the run at this step (counted from the run's start)
  std::int64_t sample_every = 100;
  std::string output;  ///< cell trajectories (HDF5); "" = none
  int pillars = 0;     ///< end the run once every cell has passed this many columns (0: off)
  bool stop_when_mode_certain = false;  ///< end the run once every cell's mode is certain
  std::string checkpoint;               ///< checkpoint file ("" = none), written when the run ends
  std::int64_t checkpoint_every = 0;    ///< and every this many steps (0: only at the end)
  /// Start from these checkpoints of one step (this process's own, or those of every process of
  /// any split: membrane/run_checkpoint.hpp); `steps` stays the last step.
  std::vector<std::string> resume;
  coupler::SecurityArgs security;  ///< tcp: CURVE key files or --plain-tcp
  /// Exchange with the fluid every step even while the forces are held ([coupling] force_every >
  /// 1), instead of letting the fluid run the held steps: the same results, slower (for checks).
  bool exchange_every_step = false;
};

/// Runs this process's share of the scene's cells against dld-fluid; returns the exit code.
int run_coupled(const Scene& scene, const MembraneScene& m, const CoupledArgs& args);

}  // namespace dld::membrane
