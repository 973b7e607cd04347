// SPDX-License-Identifier: MIT
#include "coupler/fluid_side.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cassert>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/fluid_side_detail.hpp"
#include "coupler/frame.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

namespace {

constexpr const char* kSelf = detail::kFluidSelf;
using detail::seconds;

}  // namespace

FluidSide::FluidSide(FluidConfig config) : config_(std::move(config)) {
  own_context_ = std::make_unique<zmq::context_t>(1);
  open(*own_context_);
}

FluidSide::FluidSide(FluidConfig config, zmq::context_t& context) : config_(std::move(config)) {
  open(context);
}

void FluidSide::open(zmq::context_t& context) {
  if (config_.endpoints.empty()) {
    throw InputError("fluid: coupler needs at least one membrane endpoint");
  }
  if (!config_.cell_nodes.empty() && config_.cell_nodes.size() != config_.scene.total_cells) {
    throw InputError(fmt::format("fluid: coupler given {} expected cell node counts for {} cells",
                                 config_.cell_nodes.size(), config_.scene.total_cells));
  }
  if (config_.options.curve) {  // before any bind: no handshake without the guard
    zap_ = std::make_unique<ZapGuard>(context, config_.options.curve->client_publics, kSelf);
  }
  std::vector<std::pair<zmq::socket_t*, std::string>> servers;
  for (std::size_t k = 0; k < config_.endpoints.size(); ++k) {
    Peer peer;
    peer.channel = std::make_unique<Channel>(context, Channel::Role::bind, config_.endpoints[k],
                                             config_.options, kSelf);
    peer.label = fmt::format("membrane peer {}", k);
    servers.emplace_back(&peer.channel->socket(), peer.label);
    peers_.push_back(std::move(peer));
  }
  if (zap_) zap_->start(servers);
  step_ = config_.scene.start_step;
}

FluidSide::~FluidSide() {
  if (state_ == State::running || state_ == State::have_step) {
    broadcast_error(fmt::format("fluid closed without finalize() at step {}", step_));
  }
}

std::vector<std::string> FluidSide::endpoints() const {
  std::vector<std::string> bound;
  for (const auto& peer : peers_) {
    bound.push_back(peer.channel->endpoint());
  }
  return bound;
}

template <class Body>
auto FluidSide::guarded(Body&& body) {
  try {
    return body();
  } catch (const CouplerError& e) {
    broadcast_error(e.what());
    state_ = State::failed;
    throw;
  } catch (const zmq::error_t& e) {
    const std::string message =
        fmt::format("{}: transport failed at step {}: {}", kSelf, step_, e.what());
    broadcast_error(message);
    state_ = State::failed;
    throw CouplerError(message);
  }
}

void FluidSide::initialize() {
  check_call(kSelf, "initialize()", state_, {State::created});
  guarded([&] {
    receive_hellos();
    check_hellos();
    check_halo_widths();
    map_segments();
    for (std::size_t k = 0; k < peers_.size(); ++k) {
      Peer& peer = peers_[k];
      Handshake welcome = peer.hello;
      welcome.scene = config_.scene;
      welcome.side_name = kSelf;
      welcome.shared_memory = peer.segment.mapped() ? peer.segment.name() : "";
      welcome.cell_faces.clear();  // the surfaces travel one way only
      welcome.faces.clear();
      welcome.contact_halo = halo_;
      zmq::message_t frame = encode_handshake(FrameType::welcome, welcome);
      if (!peer.channel->send(frame)) {
        throw CouplerError(fmt::format("{}: {} did not take the welcome within {} s", kSelf,
                                       peer.label, seconds(config_.options.timeout)));
      }
    }
    if (halo_ > 0) {
      receive_start_positions();
      send_halos(positions_, step_);
    }
    state_ = State::running;
    spdlog::debug("coupler: fluid serves {} membrane peer(s), {} cells, {} nodes", peers_.size(),
                  cell_nodes_.size(), node_count());
  });
}

std::vector<std::size_t> FluidSide::poll(const std::vector<std::size_t>& pending,
                                         std::chrono::steady_clock::time_point deadline) {
  std::vector<zmq::pollitem_t> items;
  items.reserve(pending.size());
  for (std::size_t k : pending) {
    items.push_back({static_cast<void*>(peers_[k].channel->socket()), 0, ZMQ_POLLIN, 0});
  }
  if (poll_for(items, deadline) == 0) {
    return {};
  }
  std::vector<std::size_t> ready;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].revents & ZMQ_POLLIN) {
      ready.push_back(pending[i]);
    }
  }
  return ready;
}

bool FluidSide::receive() {
  check_call(kSelf, "receive()", state_, {State::running});
  return guarded([&] { return receive_steps(); });
}

bool FluidSide::receive_steps() {
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    peers_[k].shut_down = false;
    pending.push_back(k);
  }
  const auto deadline = std::chrono::steady_clock::now() + config_.options.timeout;
  while (!pending.empty()) {
    const auto ready = poll(pending, deadline);
    if (ready.empty()) {
      throw CouplerError(fmt::format(
          "{}: no frame from {} within {} s while waiting for step {} (peer dead or hung?)", kSelf,
          peers_[pending.front()].label, seconds(config_.options.timeout), step_));
    }
    for (std::size_t k : ready) {
      auto frame = peers_[k].channel->receive(std::chrono::milliseconds{0});
      assert(frame);
      accept_frame(k, std::move(*frame));
      std::erase(pending, k);
    }
  }
  std::size_t shut = 0;
  for (const Peer& peer : peers_) {
    shut += peer.shut_down ? 1 : 0;
  }
  if (shut == peers_.size()) {
    state_ = State::ended;
    spdlog::debug("coupler: membranes ended the run at step {}", step_);
    return false;
  }
  if (shut > 0) {
    std::size_t a = 0;
    std::size_t b = 0;
    while (!peers_[a].shut_down) {
      ++a;
    }
    while (peers_[b].shut_down) {
      ++b;
    }
    throw CouplerError(fmt::format(
        "{}: {} ended the run at step {} while {} sent that step: membrane programs must stop "
        "together",
        kSelf, peers_[a].label, step_, peers_[b].label));
  }
  agree_on_held_steps();
  state_ = State::have_step;
  return true;
}

void FluidSide::agree_on_held_steps() {
  held_steps_ = peers_.front().held_steps;
  for (const Peer& peer : peers_) {
    if (peer.held_steps != held_steps_) {
      throw CouplerError(fmt::format(
          "{}: {} holds its forces for {} step(s) from step {} and {} for {}: membrane programs "
          "must hold the same steps",
          kSelf, peers_.front().label, held_steps_, step_, peer.label, peer.held_steps));
    }
  }
}

void FluidSide::accept_frame(std::size_t k, zmq::message_t received) {
  Peer& peer = peers_[k];
  // Keep the frame first: a small message's bytes live inside the message object and move with it.
  peer.last_frame = std::move(received);
  const zmq::message_t& frame = peer.last_frame;
  const Link link{kSelf, peer.label};
  const FrameHeader header = read_header(frame, link, step_);
  switch (header.type) {
    case FrameType::error:
      throw CouplerError(fmt::format("{}: {} reported an error at step {}: {}", kSelf, peer.label,
                                     header.step, read_error_text(frame, header)));
    case FrameType::shutdown:
      peer.shut_down = true;
      return;
    default:
      break;
  }
  const bool shared = peer.segment.mapped();
  const bool held =
      header.type == FrameType::held_steps || header.type == FrameType::held_steps_shared;
  const FrameType expected = held ? (shared ? FrameType::held_steps_shared : FrameType::held_steps)
                                  : (shared ? FrameType::step_shared : FrameType::step);
  require_data_frame(header, expected, step_, link);
  const int arrays = shared ? kSharedFrameArrays : kStepFrameArrays;
  const HeldSteps h = held ? read_held_steps(frame, header, peer.nodes, arrays, link)
                           : HeldSteps{1, read_nodes(frame, header, peer.nodes, arrays, link)};
  peer.held_steps = h.steps;
  const std::byte* data = h.data;
  if (shared) {
    peer.segment.require_size(kSelf, peer.label);
    data = peer.segment.data();
  }
  const std::size_t values = 3 * peer.nodes;
  require_finite(data, peer.nodes, "positions", link, step_);
  require_finite(data + values * sizeof(double), peer.nodes, "forces", link, step_);
  if (peers_.size() == 1 && reinterpret_cast<std::uintptr_t>(data) % alignof(double) == 0) {
    // The frame's bytes are the doubles the membrane sent (same layout, little-endian host).
    const auto* doubles = reinterpret_cast<const double*>(data);
    positions_view_ = {doubles, values};
    forces_view_ = {doubles + values, values};
    return;
  }
  std::memcpy(positions_.data() + 3 * peer.first_node, data, values * sizeof(double));
  std::memcpy(forces_.data() + 3 * peer.first_node, data + values * sizeof(double),
              values * sizeof(double));
  positions_view_ = positions_;
  forces_view_ = forces_;
}

std::span<const double> FluidSide::positions() const {
  check_call(kSelf, "positions()", state_, {State::have_step});
  return positions_view_;
}

std::span<const double> FluidSide::forces() const {
  check_call(kSelf, "forces()", state_, {State::have_step});
  return forces_view_;
}

void FluidSide::send_nodes(Peer& peer, std::span<const double> values, bool positions) {
  const auto mine = values.subspan(3 * peer.first_node, 3 * peer.nodes);
  zmq::message_t frame;
  if (peer.segment.mapped()) {
    peer.segment.require_size(kSelf, peer.label);
    double* to = peer.segment.array(
        positions ? SegmentArray::kPositions : SegmentArray::kVelocities, peer.nodes);
    if (static_cast<const void*>(to) != static_cast<const void*>(mine.data())) {
      std::memcpy(to, mine.data(), mine.size_bytes());  // not written through the buffer
    }
    frame = encode_count(positions ? FrameType::positions_shared : FrameType::velocities_shared,
                         step_, peer.nodes);
  } else {
    frame =
        positions ? encode_positions(step_, mine, &pool_) : encode_velocities(step_, mine, &pool_);
  }
  if (!peer.channel->send(frame)) {
    throw CouplerError(fmt::format("{}: {} did not take the {} of step {} within {} s", kSelf,
                                   peer.label, positions ? "positions" : "velocities", step_,
                                   seconds(config_.options.timeout)));
  }
}

void FluidSide::send_velocities(std::span<const double> velocities) {
  check_call(kSelf, "send_velocities()", state_, {State::have_step});
  if (velocities.size() != positions_.size()) {
    throw std::invalid_argument(fmt::format("fluid: send_velocities() given {} values for {} nodes",
                                            velocities.size(), node_count()));
  }
  if (held_steps_ != 1) {
    throw std::logic_error(fmt::format(
        "fluid: send_velocities() after frames of {} held steps (send_positions() completes them)",
        held_steps_));
  }
  guarded([&] {
    for (Peer& peer : peers_) send_nodes(peer, velocities, false);
    if (halo_ > 0) {
      // Where the nodes are next step: the membranes move them by X += U dt with dt = 1, and
      // x + u is that sum bit for bit.
      const std::span<const double> x = positions_view_;
      next_positions_.resize(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) next_positions_[i] = x[i] + velocities[i];
      send_halos(next_positions_, step_ + 1);
    }
    ++step_;
    state_ = State::running;
  });
}

void FluidSide::send_positions(std::span<const double> positions) {
  check_call(kSelf, "send_positions()", state_, {State::have_step});
  if (positions.size() != positions_.size()) {
    throw std::invalid_argument(fmt::format("fluid: send_positions() given {} values for {} nodes",
                                            positions.size(), node_count()));
  }
  if (held_steps_ == 1) {
    throw std::logic_error("fluid: send_positions() after a one-step frame (send_velocities())");
  }
  guarded([&] {
    for (Peer& peer : peers_) send_nodes(peer, positions, true);
    if (halo_ > 0) send_halos(positions, step_ + held_steps_);
    step_ += held_steps_;
    state_ = State::running;
  });
}

std::span<double> FluidSide::velocities_buffer() {
  check_call(kSelf, "velocities_buffer()", state_, {State::have_step});
  if (peers_.size() == 1 && peers_[0].segment.mapped()) {
    return {peers_[0].segment.array(SegmentArray::kVelocities, peers_[0].nodes),
            3 * peers_[0].nodes};
  }
  velocities_.resize(positions_.size());
  return velocities_;
}

void FluidSide::finalize() {
  check_call(kSelf, "finalize()", state_,
             {State::running, State::have_step, State::ended, State::failed});
  if (state_ == State::running || state_ == State::have_step) {
    for (Peer& peer : peers_) {
      peer.channel->try_send(encode_shutdown(step_));
    }
  }
  state_ = State::finalized;
  peers_.clear();  // close now; linger bounds the delivery of the shutdown frames
}

void FluidSide::abort(std::string_view message) noexcept {
  if (state_ == State::finalized || state_ == State::failed) {
    return;
  }
  broadcast_error(message);
  state_ = State::failed;
}

void FluidSide::broadcast_error(std::string_view message) noexcept {
  for (Peer& peer : peers_) {
    peer.channel->try_send(encode_error(step_, message));
  }
}

}  // namespace dld::coupler
