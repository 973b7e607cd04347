// SPDX-License-Identifier: MIT
// FluidSide's contact halo (docs/protocol.md, "The contact halo"): the width the peers ask for,
// their start positions, and the halo frames sent after the velocities.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cassert>
#include <cstring>

#include "coupler/error.hpp"
#include "coupler/fluid_side.hpp"
#include "coupler/fluid_side_detail.hpp"
#include "coupler/frame.hpp"

namespace dld::coupler {

namespace {
constexpr const char* kSelf = detail::kFluidSelf;
using detail::seconds;
}  // namespace

// Every peer asks for the same width (they read the same scene); with one peer there is nobody
// else's cell to see, so none is served.
void FluidSide::check_halo_widths() {
  const double width = peers_.front().hello.contact_halo;
  for (const Peer& peer : peers_) {
    if (peer.hello.contact_halo != width) {
      throw CouplerError(fmt::format(
          "{}: {}", kSelf, mismatch("contact_halo", width, peer.label, peer.hello.contact_halo)));
    }
  }
  halo_ = peers_.size() > 1 ? width : 0.0;
  if (halo_ > 0 && !(box_.lambda > 0)) {
    throw CouplerError(fmt::format(
        "{}: the membranes ask for a contact halo of {} but the fluid was given no periodic box",
        kSelf, halo_));
  }
  first_cell_.assign(1, 0);
  for (const Peer& peer : peers_) {
    first_cell_.push_back(first_cell_.back() +
                          static_cast<std::uint32_t>(peer.hello.cell_nodes.size()));
  }
  cell_first_node_.assign(1, 0);
  for (std::uint32_t n : cell_nodes_) cell_first_node_.push_back(cell_first_node_.back() + n);
}

void FluidSide::receive_start_positions() {
  std::vector<std::size_t> pending;
  for (std::size_t k = 0; k < peers_.size(); ++k) pending.push_back(k);
  const auto deadline = std::chrono::steady_clock::now() + config_.options.timeout;
  while (!pending.empty()) {
    const auto ready = poll(pending, deadline);
    if (ready.empty()) {
      throw CouplerError(fmt::format("{}: no start positions from {} within {} s", kSelf,
                                     peers_[pending.front()].label,
                                     seconds(config_.options.timeout)));
    }
    for (std::size_t k : ready) {
      Peer& peer = peers_[k];
      auto frame = peer.channel->receive(std::chrono::milliseconds{0});
      assert(frame);
      const Link link{kSelf, peer.label};
      const FrameHeader header = read_header(*frame, link, step_);
      if (header.type == FrameType::error) {
        throw CouplerError(fmt::format("{}: {} reported an error at step {}: {}", kSelf, peer.label,
                                       header.step, read_error_text(*frame, header)));
      }
      require_data_frame(header, FrameType::start_positions, step_, link);
      const std::byte* data = read_nodes(*frame, header, peer.nodes, 1, link);
      require_finite(data, peer.nodes, "start positions", link, step_);
      std::memcpy(positions_.data() + 3 * peer.first_node, data, 24 * peer.nodes);
      std::erase(pending, k);
    }
  }
}

void FluidSide::send_halos(std::span<const double> positions, std::uint64_t step) {
  const auto halos = select_halos(positions, cell_nodes_, first_cell_, halo_, box_);
  for (std::size_t k = 0; k < peers_.size(); ++k) {
    zmq::message_t frame = encode_halo(step, halos[k], cell_nodes_, cell_first_node_, positions);
    halo_cells_sent_ += halos[k].size();
    halo_bytes_sent_ += frame.size();
    if (!peers_[k].channel->send(frame)) {
      throw CouplerError(fmt::format("{}: {} did not take the contact halo of step {} within {} s",
                                     kSelf, peers_[k].label, step,
                                     seconds(config_.options.timeout)));
    }
  }
}

}  // namespace dld::coupler
