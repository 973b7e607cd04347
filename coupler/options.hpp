// SPDX-License-Identifier: MIT
#pragma once
#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace dld::coupler {

/// CURVE keys (Z85 text, 40 characters each, from zmq_curve_keypair; files: curve_keys.hpp). The
/// fluid is the server and needs its secret key and the public keys of the clients it admits;
/// each membrane is a client and needs the server's public key and a key pair of its own. Meant
/// for tcp (the programs require it there, coupler/tcp_security.hpp); ipc and inproc gain nothing.
struct CurveKeys {
  std::string server_public;
  std::string server_secret;                ///< fluid only
  std::string client_public;                ///< membrane only
  std::string client_secret;                ///< membrane only
  std::vector<std::string> client_publics;  ///< fluid only: the clients admitted (none: nobody)
};

/// Liveness and security knobs of one side. Every wait is bounded by one of these times, so a dead
/// or hung peer stops this side with a message instead of blocking it.
struct Options {
  /// Longest wait for the peer's next frame (or for it to take ours) once the run has started.
  std::chrono::milliseconds timeout{30'000};
  /// Longest wait for the hello/welcome: the peer program may still be starting.
  std::chrono::milliseconds handshake_timeout{60'000};
  /// How long closing may wait to deliver a last frame (shutdown, error): close never hangs longer.
  std::chrono::milliseconds linger{2'000};
  /// On ipc, move node arrays through a shared-memory segment and only small frames through the
  /// socket. Used when both sides allow it; either side may refuse (then frames carry the data).
  bool shared_memory = true;
  /// Authenticate and encrypt with CURVE (tcp across machines). Both sides must agree.
  std::optional<CurveKeys> curve;
};

}  // namespace dld::coupler
