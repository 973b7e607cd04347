// SPDX-License-Identifier: MIT
// One link to one peer: a ZeroMQ PAIR socket whose every wait is bounded (docs/protocol.md,
// "Transports" says why PAIR).
#pragma once
#include <chrono>
#include <optional>
#include <string>
#include <vector>
#include <zmq.hpp>

#include "coupler/options.hpp"

namespace dld::coupler {

/// zmq::poll until one item is ready or the deadline passes (0 then); a signal does not cut the
/// wait short.
int poll_for(std::vector<zmq::pollitem_t>& items, std::chrono::steady_clock::time_point deadline);

class Channel {
 public:
  enum class Role { bind, connect };

  /// Binds (fluid) or connects (membrane) `endpoint`. Throws CouplerError if binding fails (address
  /// in use, directory missing) and InputError for a malformed endpoint. `self` names the side in
  /// those messages.
  Channel(zmq::context_t& context, Role role, const std::string& endpoint, const Options& options,
          const std::string& self);

  /// The endpoint as bound: for "tcp://127.0.0.1:*" the port the system chose.
  const std::string& endpoint() const { return endpoint_; }

  /// Queues a frame; false if the peer has not taken it within `options.timeout`.
  [[nodiscard]] bool send(zmq::message_t& frame);
  /// Queues a frame if that is possible at once (error and shutdown frames on the way out).
  void try_send(zmq::message_t&& frame) noexcept;
  /// The next frame, or nothing if none arrives within `timeout`.
  std::optional<zmq::message_t> receive(std::chrono::milliseconds timeout);

  zmq::socket_t& socket() { return socket_; }

 private:
  zmq::socket_t socket_;
  std::string endpoint_;
};

}  // namespace dld::coupler
