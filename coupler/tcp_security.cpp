// SPDX-License-Identifier: MIT
#include "coupler/tcp_security.hpp"

#include <fmt/format.h>

#include "coupler/curve_keys.hpp"
#include "coupler/endpoint.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

bool is_loopback(const std::string& endpoint) {
  const std::string scheme = "tcp://";
  if (endpoint.rfind(scheme, 0) != 0) return false;
  const std::string host = endpoint.substr(scheme.size(), endpoint.rfind(':') - scheme.size());
  return host.rfind("127.", 0) == 0 || host == "localhost" || host == "[::1]";
}

std::optional<CurveKeys> curve_for(const std::string& endpoint, const SecurityArgs& args, Side side,
                                   const std::string& program) {
  if (parse_endpoint(endpoint) != Transport::tcp) return std::nullopt;
  const bool server = side == Side::server;
  const bool any_key = !args.key.empty() || !args.clients.empty() || !args.server.empty();
  if (args.plain_tcp) {
    if (any_key)
      throw InputError(fmt::format("{}: --plain-tcp with CURVE key files: choose one", program));
    if (!is_loopback(endpoint)) {
      throw InputError(fmt::format(
          "{}: --plain-tcp: {} is not a loopback address (127.0.0.0/8, localhost, [::1]); beyond "
          "this machine tcp needs CURVE keys",
          program, endpoint));
    }
    return std::nullopt;
  }
  const bool complete =
      !args.key.empty() && (server ? !args.clients.empty() : !args.server.empty());
  if (!complete) {
    throw InputError(fmt::format(
        "{}: {} {}: tcp needs CURVE keys: --curve-key FILE (this side's pair) and {} (dld-keys "
        "makes them), or --plain-tcp on a loopback address",
        program, server ? "--serve" : "--connect", endpoint,
        server ? "--curve-clients FILE... (the membranes' public keys)"
               : "--curve-server FILE (the fluid's public key)"));
  }
  const KeyPair own = read_key_file(args.key, true);
  CurveKeys keys;
  if (server) {
    keys.server_public = own.public_key;
    keys.server_secret = own.secret_key;
    keys.client_publics = read_public_keys(args.clients);
  } else {
    keys.server_public = read_key_file(args.server, false).public_key;
    keys.client_public = own.public_key;
    keys.client_secret = own.secret_key;
  }
  return keys;
}

}  // namespace dld::coupler
