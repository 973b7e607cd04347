// SPDX-License-Identifier: MIT
// FluidSide's handshake (docs/protocol.md, "The handshake"): every peer's hello, the checks in
// peer order, and the shared-memory segments the fluid accepts.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdint>
#include <cstring>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/fluid_side.hpp"
#include "coupler/fluid_side_detail.hpp"
#include "coupler/frame.hpp"

namespace dld::coupler {

namespace {

constexpr const char* kSelf = detail::kFluidSelf;
using detail::seconds;

// A hello of another protocol version may have another layout: compare the version before
// decoding anything else, so the message is a handshake mismatch and not "malformed".
void check_version(const zmq::message_t& frame, const std::string& label) {
  std::uint32_t magic = 0;
  std::uint16_t version = 0;
  if (frame.size() < kHeaderBytes) {
    return;  // read_header names it
  }
  std::memcpy(&magic, frame.data(), 4);
  std::memcpy(&version, static_cast<const std::byte*>(frame.data()) + 4, 2);
  if (magic == kMagic && version != kProtocolVersion) {
    throw CouplerError(fmt::format("{}: {}", kSelf,
                                   mismatch("protocol_version", kProtocolVersion, label, version)));
  }
}

}  // namespace

void FluidSide::receive_hellos() {
  std::vector<std::size_t> pending(peers_.size());
  for (std::size_t k = 0; k < pending.size(); ++k) {
    pending[k] = k;
  }
  const auto deadline = std::chrono::steady_clock::now() + config_.options.handshake_timeout;
  while (!pending.empty()) {
    const auto ready = poll(pending, deadline);
    if (ready.empty()) {
      const Peer& late = peers_[pending.front()];
      throw CouplerError(fmt::format(
          "{}: no hello from {} on '{}' within {} s (is that membrane program running?)", kSelf,
          late.label, late.channel->endpoint(), seconds(config_.options.handshake_timeout)));
    }
    for (std::size_t k : ready) {
      Peer& peer = peers_[k];
      auto frame = peer.channel->receive(std::chrono::milliseconds{0});
      assert(frame);
      check_version(*frame, peer.label);
      const Link link{kSelf, peer.label};
      const FrameHeader header = read_header(*frame, link, step_);
      if (header.type == FrameType::error) {
        throw CouplerError(fmt::format("{}: {} reported an error at step {}: {}", kSelf, peer.label,
                                       header.step, read_error_text(*frame, header)));
      }
      if (header.type != FrameType::hello) {
        throw_malformed(link, step_, "type",
                        fmt::format("expected hello, got {}", to_string(header.type)));
      }
      peer.hello = decode_handshake(*frame, header, link);
      if (peer.hello.side_name.empty()) {
        throw_malformed(link, step_, "side_name", "empty");
      }
      peer.label = membrane_label(peer.hello.side_name);
      std::erase(pending, k);
    }
  }
}

void FluidSide::check_hellos() {
  const auto fail = [](const std::string& what) {
    throw CouplerError(fmt::format("{}: {}", kSelf, what));
  };
  const auto total = config_.scene.total_cells;
  std::uint32_t next_cell = 0;
  std::size_t next_node = 0;
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    Peer& peer = peers_[k];
    const Handshake& hello = peer.hello;
    if (auto what = scene_mismatch(config_.scene, hello.scene, peer.label)) {
      fail(*what);
    }
    if (hello.peer_count != peers_.size()) {
      fail(mismatch("peer_count", peers_.size(), peer.label, hello.peer_count));
    }
    if (hello.peer_index != k) {
      fail(mismatch("peer_index", k, peer.label, hello.peer_index));
    }
    if (hello.first_cell != next_cell) {
      fail(mismatch("first_cell", next_cell, peer.label, hello.first_cell));
    }
    for (std::size_t i = 0; i < hello.cell_nodes.size(); ++i) {
      const std::size_t cell = next_cell + i;
      const std::string field = fmt::format("cell_nodes[{}]", cell);
      if (cell >= total) {
        fail(fmt::format("handshake: field '{}': fluid expects {} cells, {} owns cells up to {}",
                         field, total, peer.label, next_cell + hello.cell_nodes.size() - 1));
      }
      if (!config_.cell_nodes.empty() && config_.cell_nodes[cell] != hello.cell_nodes[i]) {
        fail(mismatch(field, config_.cell_nodes[cell], peer.label, hello.cell_nodes[i]));
      }
      if (hello.cell_nodes[i] == 0) {
        fail(mismatch(field, "nodes > 0", peer.label, 0));
      }
      peer.nodes += hello.cell_nodes[i];
    }
    peer.first_node = next_node;
    next_node += peer.nodes;
    next_cell += static_cast<std::uint32_t>(hello.cell_nodes.size());
    cell_nodes_.insert(cell_nodes_.end(), hello.cell_nodes.begin(), hello.cell_nodes.end());
    if (hello.cell_faces.empty()) {
      cell_faces_.insert(cell_faces_.end(), hello.cell_nodes.size(), 0);
    } else {
      cell_faces_.insert(cell_faces_.end(), hello.cell_faces.begin(), hello.cell_faces.end());
    }
    faces_.insert(faces_.end(), hello.faces.begin(), hello.faces.end());
  }
  if (next_cell != total) {
    fail(
        fmt::format("handshake: field 'total_cells': fluid expects {} cells, the {} membrane "
                    "peer(s) own {}",
                    total, peers_.size(), next_cell));
  }
  positions_.assign(3 * next_node, 0.0);
  forces_.assign(3 * next_node, 0.0);
}

// A peer's offer of a shared segment is taken on ipc if this side allows it; a segment that cannot
// be mapped is declined (the frames then carry the data), not an error.
void FluidSide::map_segments() {
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    Peer& peer = peers_[k];
    if (peer.hello.shared_memory.empty() || !config_.options.shared_memory ||
        parse_endpoint(config_.endpoints[k]) != Transport::ipc) {
      continue;
    }
    try {
      peer.segment =
          SharedSegment::open(peer.hello.shared_memory, segment_bytes(peer.nodes), kSelf);
    } catch (const CouplerError& e) {
      spdlog::debug("coupler: {} (frames will carry the data)", e.what());
    }
  }
}

}  // namespace dld::coupler
