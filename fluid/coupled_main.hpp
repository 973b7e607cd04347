// SPDX-License-Identifier: MIT
#pragma once
#include <cstdint>
#include <string>

#include "coupler/tcp_security.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

struct CoupledOptions {
  std::string endpoint;  ///< base endpoint; peer k uses coupler::peer_endpoints(endpoint, peers)[k]
  int peers = 1;         ///< membrane processes
  int cells = 0;         ///< total cells over all membrane processes
  std::string output;    ///< fluid part of the run file ("" = none)
  std::string checkpoint;             ///< checkpoint file ("" = none): written every
  std::int64_t checkpoint_every = 0;  ///< ... this many steps (0: only when the run ends)
  std::string resume;                 ///< start from this checkpoint ("" = from rest)
  coupler::SecurityArgs security;     ///< tcp: CURVE key files or --plain-tcp
};

/// Serves membrane programs until they end the run; returns the process exit code.
int serve_coupled(const Scene& scene, const CoupledOptions& options);

}  // namespace dld::fluid
