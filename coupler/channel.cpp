// SPDX-License-Identifier: MIT
#include "coupler/channel.hpp"

#include <fmt/format.h>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"

namespace dld::coupler {

Channel::Channel(zmq::context_t& context, Role role, const std::string& endpoint,
                 const Options& options, const std::string& self)
    : socket_(context, zmq::socket_type::pair), endpoint_(endpoint) {
  parse_endpoint(endpoint);
  // Linger bounds close(); the send timeout bounds a send to a peer that stopped reading.
  socket_.set(zmq::sockopt::linger, static_cast<int>(options.linger.count()));
  socket_.set(zmq::sockopt::sndtimeo, static_cast<int>(options.timeout.count()));
  if (options.curve) {
    const CurveKeys& keys = *options.curve;
    if (role == Role::bind) {
      socket_.set(zmq::sockopt::curve_server, 1);
      socket_.set(zmq::sockopt::curve_secretkey, keys.server_secret);
    } else {
      socket_.set(zmq::sockopt::curve_serverkey, keys.server_public);
      socket_.set(zmq::sockopt::curve_publickey, keys.client_public);
      socket_.set(zmq::sockopt::curve_secretkey, keys.client_secret);
    }
  }
  try {
    if (role == Role::bind) {
      socket_.bind(endpoint);
      endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
    } else {
      socket_.connect(endpoint);
    }
  } catch (const zmq::error_t& e) {
    throw CouplerError(fmt::format("{}: cannot {} '{}': {}", self,
                                   role == Role::bind ? "bind" : "connect", endpoint, e.what()));
  }
  if (endpoint_.empty()) endpoint_ = endpoint;  // inproc reports no last endpoint on some versions
}

bool Channel::send(zmq::message_t& frame) {
  return socket_.send(frame, zmq::send_flags::none).has_value();
}

void Channel::try_send(zmq::message_t&& frame) noexcept {
  try {
    (void)socket_.send(frame, zmq::send_flags::dontwait);
  } catch (...) {
    // Best effort on the way out: the peer's timeout is the backstop.
  }
}

std::optional<zmq::message_t> Channel::receive(std::chrono::milliseconds timeout) {
  zmq::pollitem_t item{static_cast<void*>(socket_), 0, ZMQ_POLLIN, 0};
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (zmq::poll(&item, 1, std::max(left, std::chrono::milliseconds{0})) > 0) break;
    if (left.count() <= 0) return std::nullopt;
  }
  zmq::message_t frame;
  if (!socket_.recv(frame, zmq::recv_flags::dontwait)) return std::nullopt;
  return frame;
}

}  // namespace dld::coupler
