// SPDX-License-Identifier: MIT
// The programs' rule for tcp (docs/protocol.md, "Security"): CURVE on every tcp endpoint, keys
// from files; plain tcp only when asked for and only on a loopback address. ipc and inproc are
// reachable only from this machine (file permissions) and need no keys.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "coupler/options.hpp"

namespace dld::coupler {

/// What a program was given on its command line (coupler/security_options.hpp adds the options).
struct SecurityArgs {
  std::string key;                   ///< this side's key pair (a .key file)
  std::vector<std::string> clients;  ///< fluid: the key files of the clients it admits
  std::string server;                ///< client: the fluid's public key (.pub or .key)
  bool plain_tcp = false;            ///< the explicit opt-out, loopback only
};

enum class Side { server, client };

/// True for tcp://127.x.x.x:port, tcp://localhost:port and tcp://[::1]:port.
bool is_loopback(const std::string& endpoint);

/// The CURVE keys for `endpoint` (nothing for ipc and inproc, or with --plain-tcp on loopback).
/// Throws dld::InputError naming the program and option: tcp without keys, --plain-tcp beyond
/// loopback, keys and --plain-tcp together, a bad key file.
std::optional<CurveKeys> curve_for(const std::string& endpoint, const SecurityArgs& args, Side side,
                                   const std::string& program);

}  // namespace dld::coupler
