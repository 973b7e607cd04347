// SPDX-License-Identifier: MIT
#include "coupler/endpoint.hpp"

#include <fmt/format.h>

#include <charconv>

#include "shared/input_error.hpp"

namespace dld::coupler {

namespace {

// sockaddr_un::sun_path holds 108 bytes including the terminating zero.
constexpr std::size_t kMaxIpcPath = 107;

[[noreturn]] void bad(std::string_view endpoint, std::string_view why) {
  throw InputError(fmt::format("coupler endpoint '{}': {}", endpoint, why));
}

}  // namespace

Transport parse_endpoint(std::string_view endpoint) {
  const auto rest = [&](std::string_view scheme) { return endpoint.substr(scheme.size()); };
  if (endpoint.starts_with("inproc://")) {
    if (rest("inproc://").empty()) {
      bad(endpoint, "empty inproc name");
    }
    return Transport::inproc;
  }
  if (endpoint.starts_with("ipc://")) {
    const auto path = rest("ipc://");
    if (path.empty()) {
      bad(endpoint, "empty ipc path");
    }
    if (path.size() > kMaxIpcPath) {
      bad(endpoint, fmt::format("ipc path of {} bytes is longer than the {} a Unix socket allows",
                                path.size(), kMaxIpcPath));
    }
    return Transport::ipc;
  }
  if (endpoint.starts_with("tcp://")) {
    const auto address = rest("tcp://");
    const auto colon = address.rfind(':');
    if (colon == std::string_view::npos || colon == 0 || colon + 1 == address.size()) {
      bad(endpoint, "expected tcp://host:port");
    }
    return Transport::tcp;
  }
  bad(endpoint, "expected inproc://name, ipc:///path or tcp://host:port");
}

std::vector<std::string> peer_endpoints(std::string_view base, std::size_t peers) {
  const Transport transport = parse_endpoint(base);
  std::vector<std::string> endpoints;
  for (std::size_t k = 0; k < peers; ++k) {
    if (transport != Transport::tcp) {
      endpoints.push_back(fmt::format("{}-{}", base, k));
      continue;
    }
    const auto colon = base.rfind(':');
    const auto port_text = base.substr(colon + 1);
    if (port_text == "*") {
      endpoints.emplace_back(base);
      continue;
    }
    unsigned port = 0;
    const auto [end, ec] =
        std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
    if (ec != std::errc{} || end != port_text.data() + port_text.size() || port + peers > 65536) {
      bad(base, "tcp port must be a number (or *) leaving room for one port per membrane peer");
    }
    endpoints.push_back(fmt::format("{}:{}", base.substr(0, colon), port + k));
  }
  for (const auto& e : endpoints) {
    parse_endpoint(e);  // an ipc path may have grown too long
  }
  return endpoints;
}

}  // namespace dld::coupler
