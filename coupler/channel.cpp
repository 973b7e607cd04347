// SPDX-License-Identifier: MIT
#include "coupler/channel.hpp"

#include <fmt/format.h>

#include <cerrno>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"

namespace dld::coupler {

namespace {

// The fluid is the CURVE server (it binds); each membrane a client that knows the server's key.
void set_curve(zmq::socket_t& socket, Channel::Role role, const Options& options) {
  if (!options.curve) {
    return;
  }
  const CurveKeys& keys = *options.curve;
  if (role == Channel::Role::bind) {
    socket.set(zmq::sockopt::curve_server, 1);
    socket.set(zmq::sockopt::curve_secretkey, keys.server_secret);
  } else {
    socket.set(zmq::sockopt::curve_serverkey, keys.server_public);
    socket.set(zmq::sockopt::curve_publickey, keys.client_public);
    socket.set(zmq::sockopt::curve_secretkey, keys.client_secret);
  }
}

}  // namespace

Channel::Channel(zmq::context_t& context, Role role, const std::string& endpoint,
                 const Options& options, const std::string& self)
    : socket_(context, zmq::socket_type::pair), endpoint_(endpoint) {
  parse_endpoint(endpoint);
  // Linger bounds close(); the send timeout bounds a send to a peer that stopped reading.
  socket_.set(zmq::sockopt::linger, static_cast<int>(options.linger.count()));
  socket_.set(zmq::sockopt::sndtimeo, static_cast<int>(options.timeout.count()));
  try {
    set_curve(socket_, role, options);
  } catch (const zmq::error_t& e) {
    throw CouplerError(
        fmt::format("{}: CURVE keys refused for '{}' (expected 40-character Z85 "
                    "keys): {}",
                    self, endpoint, e.what()));
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
  if (endpoint_.empty()) {
    endpoint_ = endpoint;  // inproc reports no last endpoint on some versions
  }
}

bool Channel::send(zmq::message_t& frame) {
  for (;;) {
    try {
      return socket_.send(frame, zmq::send_flags::none).has_value();
    } catch (const zmq::error_t& e) {
      if (e.num() != EINTR) {
        throw;  // a signal (Ctrl-C) is the program's to handle, between steps
      }
    }
  }
}

int poll_for(std::vector<zmq::pollitem_t>& items, std::chrono::steady_clock::time_point deadline) {
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    int ready = 0;
    try {
      ready = zmq::poll(items, std::max(left, std::chrono::milliseconds{0}));
    } catch (const zmq::error_t& e) {
      if (e.num() != EINTR) {
        throw;
      }
    }
    if (ready > 0 || left.count() <= 0) {
      return ready;
    }
  }
}

void Channel::try_send(zmq::message_t&& frame) noexcept {
  try {
    (void)socket_.send(frame, zmq::send_flags::dontwait);
  } catch (...) {
    // Best effort on the way out: the peer's timeout is the backstop.
  }
}

std::optional<zmq::message_t> Channel::receive(std::chrono::milliseconds timeout) {
  std::vector<zmq::pollitem_t> item{{static_cast<void*>(socket_), 0, ZMQ_POLLIN, 0}};
  if (poll_for(item, std::chrono::steady_clock::now() + timeout) == 0) {
    return std::nullopt;
  }
  zmq::message_t frame;
  if (!socket_.recv(frame, zmq::recv_flags::dontwait)) {
    return std::nullopt;
  }
  return frame;
}

}  // namespace dld::coupler
