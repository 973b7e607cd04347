// SPDX-License-Identifier: MIT
// Endpoint strings: which transports the coupler accepts and how K peers get K endpoints.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace dld::coupler {

enum class Transport { inproc, ipc, tcp };

/// Checks an endpoint ("inproc://name", "ipc:///path/socket", "tcp://host:port") and returns its
/// transport. Throws dld::InputError naming the endpoint: unknown scheme, empty name, ipc path
/// longer than a Unix socket allows, tcp without a port.
Transport parse_endpoint(std::string_view endpoint);

/// One endpoint per membrane peer from one base: inproc and ipc append "-<k>"; tcp adds k to the
/// port (a port of "*" stays "*": the system picks one per peer).
std::vector<std::string> peer_endpoints(std::string_view base, std::size_t peers);

}  // namespace dld::coupler
