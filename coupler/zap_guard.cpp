// SPDX-License-Identifier: MIT
#include "coupler/zap_guard.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstring>

#include "coupler/curve_keys.hpp"

namespace dld::coupler {

namespace {

constexpr const char* kZapEndpoint = "inproc://zeromq.zap.01";  // fixed by RFC 27

std::string text(const zmq::message_t& m) {
  return {static_cast<const char*>(m.data()), m.size()};
}

std::vector<zmq::message_t> receive_all(zmq::socket_t& s) {
  std::vector<zmq::message_t> parts;
  do {
    parts.emplace_back();
    if (!s.recv(parts.back(), zmq::recv_flags::dontwait)) {
      parts.pop_back();
      break;
    }
  } while (parts.back().more());
  return parts;
}

std::string handshake_failure(std::uint16_t event, std::uint32_t value) {
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL &&
      value == ZMQ_PROTOCOL_ERROR_ZMTP_MECHANISM_MISMATCH)
    return "it offered no CURVE keys (a plain client)";
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL &&
      value == ZMQ_PROTOCOL_ERROR_ZMTP_CRYPTOGRAPHIC)
    return "its CURVE hello does not decrypt (it uses another server key)";
  if (event == ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL)
    return fmt::format("the CURVE handshake failed (ZMTP protocol error {:#x})", value);
  // The peer closed the connection mid-handshake: typically a plain client that saw the CURVE
  // greeting first and gave up (the two sides detect the mismatch in either order).
  return "it left during the handshake (no CURVE keys on its side, or it gave up)";
}

}  // namespace

ZapGuard::ZapGuard(zmq::context_t& context, std::vector<std::string> admitted, std::string self)
    : context_(context),
      admitted_(admitted.begin(), admitted.end()),
      self_(std::move(self)),
      zap_(context, zmq::socket_type::rep),
      stop_send_(context, zmq::socket_type::pair),
      stop_receive_(context, zmq::socket_type::pair) {
  zap_.set(zmq::sockopt::linger, 0);
  zap_.bind(kZapEndpoint);
  const std::string stop = fmt::format("inproc://dld-zap-stop-{}", static_cast<void*>(this));
  stop_receive_.bind(stop);
  stop_send_.connect(stop);
}

void ZapGuard::start(const std::vector<std::pair<zmq::socket_t*, std::string>>& servers) {
  for (const auto& [socket, label] : servers) {
    const std::string at =
        fmt::format("inproc://dld-zap-monitor-{}-{}", static_cast<void*>(this), monitors_.size());
    if (zmq_socket_monitor(
            socket->handle(), at.c_str(),
            ZMQ_EVENT_HANDSHAKE_FAILED_PROTOCOL | ZMQ_EVENT_HANDSHAKE_FAILED_NO_DETAIL) != 0)
      throw zmq::error_t();
    monitors_.emplace_back(context_, zmq::socket_type::pair);
    monitors_.back().set(zmq::sockopt::linger, 0);
    monitors_.back().connect(at);
    labels_.push_back(label);
  }
  thread_ = std::thread([this] { serve(); });
}

ZapGuard::~ZapGuard() {
  if (thread_.joinable()) {
    try {
      stop_send_.send(zmq::str_buffer("stop"), zmq::send_flags::dontwait);
    } catch (const zmq::error_t&) {
      // the thread also ends when the context terminates
    }
    thread_.join();
  }
}

void ZapGuard::serve() {
  std::vector<zmq::pollitem_t> items{{zap_.handle(), 0, ZMQ_POLLIN, 0},
                                     {stop_receive_.handle(), 0, ZMQ_POLLIN, 0}};
  for (auto& m : monitors_) items.push_back({m.handle(), 0, ZMQ_POLLIN, 0});
  try {
    for (;;) {
      zmq::poll(items, std::chrono::milliseconds{-1});
      if (items[1].revents & ZMQ_POLLIN) break;
      if (items[0].revents & ZMQ_POLLIN) answer_zap();
      for (std::size_t k = 0; k < monitors_.size(); ++k)
        if (items[k + 2].revents & ZMQ_POLLIN) read_event(k);
    }
  } catch (const zmq::error_t&) {
    // context terminated or interrupted: the guard's sockets close with the thread
  }
  for (auto& m : monitors_) m.close();
  zap_.close();
  stop_receive_.close();
}

// RFC 27: version, request id, domain, address, routing id, mechanism, credentials; the reply
// is version, request id, status code, status text, user id, metadata.
void ZapGuard::answer_zap() {
  std::vector<zmq::message_t> request = receive_all(zap_);
  if (request.size() < 6) return;
  const std::string address = text(request[3]), mechanism = text(request[5]);
  bool admit = false;
  std::string why = fmt::format("mechanism {} (expected CURVE)", mechanism);
  if (mechanism == "CURVE" && request.size() >= 7 && request[6].size() == 32) {
    const std::string key = z85_key(static_cast<const unsigned char*>(request[6].data()));
    admit = admitted_.count(key) > 0;
    why = fmt::format("its key {} is not among the run's client keys", key);
  }
  if (!admit) refuse(fmt::format("{}: refused a client from {}: {}", self_, address, why));
  const char* status = admit ? "200" : "400";
  zap_.send(zmq::str_buffer("1.0"), zmq::send_flags::sndmore);
  zap_.send(request[1], zmq::send_flags::sndmore);
  zap_.send(zmq::buffer(status, 3), zmq::send_flags::sndmore);
  zap_.send(zmq::buffer(admit ? std::string("OK") : std::string("not admitted")),
            zmq::send_flags::sndmore);
  zap_.send(zmq::str_buffer(""), zmq::send_flags::sndmore);
  zap_.send(zmq::str_buffer(""), zmq::send_flags::none);
}

void ZapGuard::read_event(std::size_t monitor) {
  std::vector<zmq::message_t> event = receive_all(monitors_[monitor]);
  if (event.size() < 2 || event[0].size() < 6) return;
  std::uint16_t id = 0;
  std::uint32_t value = 0;
  std::memcpy(&id, event[0].data(), 2);
  std::memcpy(&value, static_cast<const char*>(event[0].data()) + 2, 4);
  refuse(fmt::format("{}: refused a client connecting to {} ({}): {}", self_, text(event[1]),
                     labels_[monitor], handshake_failure(id, value)));
}

void ZapGuard::refuse(const std::string& line) {
  spdlog::warn("{}", line);
  const std::lock_guard<std::mutex> lock(mutex_);
  refusals_.push_back(line);
}

std::vector<std::string> ZapGuard::refusals() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return refusals_;
}

}  // namespace dld::coupler
