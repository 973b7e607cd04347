// SPDX-License-Identifier: MIT
// The tcp security options of the coupled programs (CLI11): dld-fluid takes --curve-key and
// --curve-clients, dld-membrane and dld-tracers --curve-key and --curve-server; all --plain-tcp.
#pragma once
#include <CLI/CLI.hpp>

#include "coupler/tcp_security.hpp"

namespace dld::coupler {

inline void add_security_options(CLI::App& app, SecurityArgs& args, Side side) {
  app.add_option("--curve-key", args.key,
                 "tcp: this program's CURVE key pair (a .key file from dld-keys)")
      ->check(CLI::ExistingFile);
  if (side == Side::server) {
    app.add_option("--curve-clients", args.clients,
                   "tcp: key files of the membrane programs admitted (their .pub files)")
        ->check(CLI::ExistingFile);
  } else {
    app.add_option("--curve-server", args.server, "tcp: the fluid's public key (its .pub file)")
        ->check(CLI::ExistingFile);
  }
  app.add_flag("--plain-tcp", args.plain_tcp,
               "tcp without CURVE (a loopback address only: anyone on the machine can connect)");
}

}  // namespace dld::coupler
