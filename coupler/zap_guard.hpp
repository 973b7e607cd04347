// SPDX-License-Identifier: MIT
// The fluid's gatekeeper on CURVE: a ZAP handler (ZeroMQ RFC 27) that admits only the client
// public keys listed for the run, and a watch on the server sockets' failed handshakes, so that
// every client turned away is named in the fluid's log: a keyless client (no CURVE), one with a
// made-up key pair (not listed), one with a wrong server key (its hello cannot be decrypted).
// Without a ZAP handler libzmq lets in any client that knows the server's public key.
#pragma once
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

namespace dld::coupler {

class ZapGuard {
 public:
  /// Binds the context's ZAP endpoint (before any server socket binds, so that no handshake is
  /// ever made without it). `self` names the side in log lines.
  ZapGuard(zmq::context_t& context, std::vector<std::string> admitted, std::string self);
  ZapGuard(const ZapGuard&) = delete;
  ZapGuard& operator=(const ZapGuard&) = delete;
  ~ZapGuard();

  /// Watches the failed handshakes of these bound server sockets (label: "membrane peer k") and
  /// starts answering ZAP requests (they wait in the queue until then).
  void start(const std::vector<std::pair<zmq::socket_t*, std::string>>& servers);

  /// Every refusal so far, as logged (one line each).
  std::vector<std::string> refusals() const;

 private:
  void serve();
  void answer_zap();
  void read_event(std::size_t monitor);
  void refuse(const std::string& line);

  zmq::context_t& context_;
  std::set<std::string> admitted_;
  std::string self_;
  zmq::socket_t zap_;
  zmq::socket_t stop_send_, stop_receive_;
  std::vector<zmq::socket_t> monitors_;
  std::vector<std::string> labels_;
  mutable std::mutex mutex_;
  std::vector<std::string> refusals_;
  std::thread thread_;
};

}  // namespace dld::coupler
