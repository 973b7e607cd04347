// SPDX-License-Identifier: MIT
#pragma once
#include <string>

#include "shared/scene.hpp"

namespace dld::fluid {

struct CoupledOptions {
  std::string endpoint;  ///< base endpoint; peer k uses coupler::peer_endpoints(endpoint, peers)[k]
  int peers = 1;         ///< membrane processes
  int cells = 0;         ///< total cells over all membrane processes
  std::string output;    ///< fluid part of the run file ("" = none)
};

/// Serves membrane programs until they end the run; returns the process exit code.
int serve_coupled(const Scene& scene, const CoupledOptions& options);

}  // namespace dld::fluid
