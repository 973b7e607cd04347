// SPDX-License-Identifier: MIT
#include "coupler/membrane_side.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/frame.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

namespace {

constexpr const char* kFluid = "fluid";

double seconds(std::chrono::milliseconds t) {
  return static_cast<double>(t.count()) / 1000.0;
}

// Data written through positions_buffer()/forces_buffer() is already in place.
void copy_unless_same(double* to, const double* from, std::size_t bytes) {
  if (static_cast<const void*>(to) != static_cast<const void*>(from)) {
    std::memcpy(to, from, bytes);
  }
}

}  // namespace

MembraneSide::MembraneSide(MembraneConfig config)
    : config_(std::move(config)), own_context_(std::make_unique<zmq::context_t>(1)) {
  self_ = membrane_label(config_.name);
  channel_ = std::make_unique<Channel>(*own_context_, Channel::Role::connect, config_.endpoint,
                                       config_.options, self_);
  step_ = config_.scene.start_step;
  nodes_ = std::accumulate(config_.cell_nodes.begin(), config_.cell_nodes.end(), std::size_t{0});
}

MembraneSide::MembraneSide(MembraneConfig config, zmq::context_t& context)
    : config_(std::move(config)) {
  self_ = membrane_label(config_.name);
  channel_ = std::make_unique<Channel>(context, Channel::Role::connect, config_.endpoint,
                                       config_.options, self_);
  step_ = config_.scene.start_step;
  nodes_ = std::accumulate(config_.cell_nodes.begin(), config_.cell_nodes.end(), std::size_t{0});
}

MembraneSide::~MembraneSide() {
  if (channel_ && (state_ == State::running)) {
    channel_->try_send(
        encode_error(step_, fmt::format("{} closed without finalize() at step {}", self_, step_)));
  }
}

template <class Body>
auto MembraneSide::guarded(Body&& body) {
  try {
    return body();
  } catch (const CouplerError& e) {
    channel_->try_send(encode_error(step_, e.what()));
    state_ = State::failed;
    throw;
  } catch (const zmq::error_t& e) {
    const std::string message =
        fmt::format("{}: transport failed at step {}: {}", self_, step_, e.what());
    channel_->try_send(encode_error(step_, message));
    state_ = State::failed;
    throw CouplerError(message);
  }
}

void MembraneSide::set_cell_surfaces(std::vector<std::uint32_t> cell_faces,
                                     std::vector<std::uint32_t> faces) {
  check_call(self_, "set_cell_surfaces()", state_, {State::created});
  if (cell_faces.size() != config_.cell_nodes.size()) {
    throw CouplerError(fmt::format("{}: surfaces for {} cells, the side owns {}", self_,
                                   cell_faces.size(), config_.cell_nodes.size()));
  }
  cell_faces_ = std::move(cell_faces);
  faces_ = std::move(faces);
}

void MembraneSide::initialize(std::span<const double> start_positions) {
  check_call(self_, "initialize()", state_, {State::created});
  if (config_.contact_halo > 0 && start_positions.size() != 3 * nodes_) {
    throw std::invalid_argument(fmt::format(
        "{}: initialize() with a contact halo needs the {} start position values, given {}", self_,
        3 * nodes_, start_positions.size()));
  }
  guarded([&] {
    Handshake hello{config_.scene,
                    config_.name,
                    config_.peer_index,
                    config_.peer_count,
                    config_.first_cell,
                    config_.cell_nodes,
                    cell_faces_,
                    faces_,
                    "",
                    config_.contact_halo};
    if (config_.options.shared_memory && nodes_ > 0 &&
        parse_endpoint(config_.endpoint) == Transport::ipc) {
      try {
        segment_ = SharedSegment::create(segment_bytes(nodes_), self_);
        hello.shared_memory = segment_.name();
      } catch (const CouplerError& e) {
        spdlog::debug("coupler: {} (frames will carry the data)", e.what());
      }
    }
    zmq::message_t frame = encode_handshake(FrameType::hello, hello);
    if (!channel_->send(frame)) {
      throw CouplerError(fmt::format("{}: the fluid did not take the hello on '{}' within {} s",
                                     self_, config_.endpoint, seconds(config_.options.timeout)));
    }
    auto reply = channel_->receive(config_.options.handshake_timeout);
    if (!reply) {
      throw CouplerError(fmt::format(
          "{}: no welcome from the fluid on '{}' within {} s (is the fluid program running?)",
          self_, config_.endpoint, seconds(config_.options.handshake_timeout)));
    }
    const Link link{self_, kFluid};
    const FrameHeader header = read_header(*reply, link, step_);
    if (header.type == FrameType::error) {
      throw CouplerError(fmt::format("{}: fluid reported an error at step {}: {}", self_,
                                     header.step, read_error_text(*reply, header)));
    }
    if (header.type != FrameType::welcome) {
      throw_malformed(link, step_, "type",
                      fmt::format("expected welcome, got {}", to_string(header.type)));
    }
    const Handshake welcome = decode_handshake(*reply, header, link);
    check_welcome(welcome);
    shared_ = !welcome.shared_memory.empty();
    segment_.unlink();  // the fluid has mapped it (or declined): the name is no longer needed
    if (!shared_) {
      segment_ = SharedSegment();
    }
    if (config_.contact_halo > 0) {
      zmq::message_t start = encode_start_positions(step_, start_positions);
      if (!channel_->send(start)) {
        throw CouplerError(fmt::format("{}: the fluid did not take the start positions within {} s",
                                       self_, seconds(config_.options.timeout)));
      }
      receive_halo();
    }
    state_ = State::running;
    spdlog::debug("coupler: {} joined the fluid with {} cells, {} nodes", self_,
                  config_.cell_nodes.size(), nodes_);
  });
}

// The fluid checks the hello first; this second look catches a fluid that skipped a check.
void MembraneSide::check_welcome(const Handshake& welcome) {
  const auto fail = [&](const std::string& what) {
    throw CouplerError(fmt::format("{}: {}", self_, what));
  };
  if (auto what = scene_mismatch(welcome.scene, config_.scene, self_)) {
    fail(*what);
  }
  if (welcome.peer_count != config_.peer_count) {
    fail(mismatch("peer_count", welcome.peer_count, self_, config_.peer_count));
  }
  if (welcome.peer_index != config_.peer_index) {
    fail(mismatch("peer_index", welcome.peer_index, self_, config_.peer_index));
  }
  if (welcome.first_cell != config_.first_cell) {
    fail(mismatch("first_cell", welcome.first_cell, self_, config_.first_cell));
  }
  if (welcome.cell_nodes != config_.cell_nodes) {
    fail(mismatch("cell_nodes", fmt::format("{} cells", welcome.cell_nodes.size()), self_,
                  fmt::format("{} cells", config_.cell_nodes.size())));
  }
  if (welcome.contact_halo != config_.contact_halo) {
    fail(mismatch("contact_halo", welcome.contact_halo, self_, config_.contact_halo));
  }
  if (!welcome.shared_memory.empty() && welcome.shared_memory != segment_.name()) {
    fail(mismatch("shared_memory", fmt::format("'{}'", welcome.shared_memory), self_,
                  fmt::format("'{}'", segment_.name())));
  }
}

bool MembraneSide::advance(std::span<const double> positions, std::span<const double> forces,
                           std::span<double> velocities) {
  check_call(self_, "advance()", state_, {State::running});
  if (velocities.size() != 3 * nodes_) {
    throw std::invalid_argument(fmt::format("{}: advance() given {} velocity values for {} nodes",
                                            self_, velocities.size(), nodes_));
  }
  const auto received = exchange(positions, forces);
  if (!received) {
    return false;
  }
  std::memcpy(velocities.data(), received->data(), received->size_bytes());
  return true;
}

std::optional<std::span<const double>> MembraneSide::exchange(std::span<const double> positions,
                                                              std::span<const double> forces) {
  return exchange_steps(positions, forces, 1);
}

bool MembraneSide::advance_held(std::span<const double> positions, std::span<const double> forces,
                                std::uint64_t n, std::span<double> positions_after) {
  check_call(self_, "advance_held()", state_, {State::running});
  if (positions_after.size() != 3 * nodes_ || n < 1 || n > kMostHeldSteps) {
    throw std::invalid_argument(fmt::format(
        "{}: advance_held() given {} position values for {} nodes and {} steps (1 to {})", self_,
        positions_after.size(), nodes_, n, kMostHeldSteps));
  }
  const auto received = exchange_steps(positions, forces, n);
  if (!received) return false;
  if (n == 1) {
    // X += U dt with dt = 1, as the fluid does in held steps (x + u, bit for bit).
    for (std::size_t i = 0; i < positions_after.size(); ++i)
      positions_after[i] = positions[i] + (*received)[i];
  } else {
    copy_unless_same(positions_after.data(), received->data(), received->size_bytes());
  }
  return true;
}

void MembraneSide::send_steps(std::span<const double> positions, std::span<const double> forces,
                              std::uint64_t n) {
  const std::size_t bytes = 3 * sizeof(double) * nodes_;
  zmq::message_t frame;
  if (shared_) {
    copy_unless_same(segment_.array(SegmentArray::kPositions, nodes_), positions.data(), bytes);
    copy_unless_same(segment_.array(SegmentArray::kForces, nodes_), forces.data(), bytes);
    frame = n == 1 ? encode_count(FrameType::step_shared, step_, nodes_)
                   : encode_held_steps_shared(step_, nodes_, n);
  } else {
    frame = n == 1 ? encode_step(step_, positions, forces, &pool_)
                   : encode_held_steps(step_, n, positions, forces, &pool_);
  }
  if (!channel_->send(frame)) {
    throw CouplerError(fmt::format("{}: the fluid did not take step {} within {} s", self_, step_,
                                   seconds(config_.options.timeout)));
  }
}

std::optional<std::span<const double>> MembraneSide::exchange_steps(
    std::span<const double> positions, std::span<const double> forces, std::uint64_t n) {
  check_call(self_, "advance()", state_, {State::running});
  if (positions.size() != 3 * nodes_ || forces.size() != 3 * nodes_) {
    throw std::invalid_argument(
        fmt::format("{}: advance() given {}/{} position/force values for "
                    "{} nodes",
                    self_, positions.size(), forces.size(), nodes_));
  }
  return guarded([&]() -> std::optional<std::span<const double>> {
    send_steps(positions, forces, n);
    // n held steps take the fluid about n times one step's time.
    const auto timeout =
        config_.options.timeout * static_cast<long>(std::min<std::uint64_t>(n, 10));
    auto reply = channel_->receive(timeout);
    // The fluid may itself be waiting, with the same timeout, for another membrane process that
    // died or hung: half a timeout more lets its error frame, which names that process, arrive
    // before this side blames the fluid.
    if (!reply) reply = channel_->receive(config_.options.timeout / 2);
    if (!reply) {
      throw CouplerError(
          fmt::format("{}: no {} from the fluid within {} s at step {} (fluid dead or hung?)",
                      self_, n == 1 ? "velocities" : "positions",
                      seconds(timeout + config_.options.timeout / 2), step_));
    }
    // Keep the frame first: a small message's bytes live inside the message object.
    reply_ = std::move(*reply);
    const Link link{self_, kFluid};
    const FrameHeader header = read_header(reply_, link, step_);
    switch (header.type) {
      case FrameType::error:
        throw CouplerError(fmt::format("{}: fluid reported an error at step {}: {}", self_,
                                       header.step, read_error_text(reply_, header)));
      case FrameType::shutdown:
        state_ = State::ended;
        spdlog::debug("coupler: fluid ended the run at step {}", step_);
        return std::nullopt;
      default:
        break;
    }
    const bool held = n > 1;
    const FrameType expected =
        held ? (shared_ ? FrameType::positions_shared : FrameType::positions)
             : (shared_ ? FrameType::velocities_shared : FrameType::velocities);
    require_data_frame(header, expected, step_, link);
    const std::byte* data = read_nodes(reply_, header, nodes_,
                                       shared_ ? kSharedFrameArrays : kVelocitiesFrameArrays, link);
    if (shared_) {
      data = reinterpret_cast<const std::byte*>(
          segment_.array(held ? SegmentArray::kPositions : SegmentArray::kVelocities, nodes_));
    }
    require_finite(data, nodes_, held ? "positions" : "velocities", link, step_);
    step_ += n;
    if (config_.contact_halo > 0) receive_halo();
    if (reinterpret_cast<std::uintptr_t>(data) % alignof(double) == 0) {
      return std::span<const double>(reinterpret_cast<const double*>(data), 3 * nodes_);
    }
    unaligned_.resize(3 * nodes_);
    std::memcpy(unaligned_.data(), data, unaligned_.size() * sizeof(double));
    return std::span<const double>(unaligned_);
  });
}

// The halo frame follows the velocities (or the welcome) and carries the cells at step_.
void MembraneSide::receive_halo() {
  auto frame = channel_->receive(config_.options.timeout);
  // The halo needs every process's nodes: the fluid may be waiting for a dead or hung one, as
  // for the velocities above; half a timeout more lets its error frame naming it arrive first.
  if (!frame) frame = channel_->receive(config_.options.timeout / 2);
  if (!frame) {
    throw CouplerError(
        fmt::format("{}: no contact halo from the fluid within {} s at step {}", self_,
                    seconds(config_.options.timeout + config_.options.timeout / 2), step_));
  }
  const Link link{self_, kFluid};
  const FrameHeader header = read_header(*frame, link, step_);
  if (header.type == FrameType::error) {
    throw CouplerError(fmt::format("{}: fluid reported an error at step {}: {}", self_, header.step,
                                   read_error_text(*frame, header)));
  }
  require_data_frame(header, FrameType::halo, step_, link);
  const auto own = static_cast<std::uint32_t>(config_.cell_nodes.size());
  halo_ = decode_halo(*frame, header, config_.first_cell, config_.first_cell + own,
                      config_.scene.total_cells, link);
}

std::span<double> MembraneSide::positions_buffer() {
  check_call(self_, "positions_buffer()", state_, {State::running});
  if (shared_) {
    return {segment_.array(SegmentArray::kPositions, nodes_), 3 * nodes_};
  }
  staging_.resize(6 * nodes_);
  return std::span<double>(staging_).first(3 * nodes_);
}

std::span<double> MembraneSide::forces_buffer() {
  check_call(self_, "forces_buffer()", state_, {State::running});
  if (shared_) {
    return {segment_.array(SegmentArray::kForces, nodes_), 3 * nodes_};
  }
  staging_.resize(6 * nodes_);
  return std::span<double>(staging_).last(3 * nodes_);
}

void MembraneSide::finalize() {
  check_call(self_, "finalize()", state_, {State::running, State::ended, State::failed});
  if (state_ == State::running) {
    channel_->try_send(encode_shutdown(step_));
  }
  state_ = State::finalized;
  channel_.reset();  // close now; linger bounds the delivery of the shutdown frame
}

void MembraneSide::abort(std::string_view message) noexcept {
  if (state_ == State::finalized || state_ == State::failed || !channel_) {
    return;
  }
  channel_->try_send(encode_error(step_, message));
  state_ = State::failed;
}

}  // namespace dld::coupler
