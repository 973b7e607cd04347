// SPDX-License-Identifier: MIT
// The fluid's end of the coupling: serves K membrane peers in lock-step.
//
// Call order (checked; a wrong order throws std::logic_error):
//   FluidSide fluid(config);             // binds one endpoint per membrane peer
//   fluid.initialize();                  // hellos in, handshake checked, welcomes out
//   while (fluid.receive()) {            // positions and forces of step fluid.step()
//     ... spread fluid.forces() at fluid.positions(), advance the lattice, interpolate ...
//     fluid.send_velocities(u);          // same nodes, same order; step += 1
//   }                                    // receive() == false: the membranes ended the run
//   fluid.finalize();                    // tells the membranes to stop if they have not
// Held steps (docs/protocol.md): when held_steps() = n > 1 the membranes hold their forces for
// steps step() to step() + n - 1; the fluid runs them, moving its copy of the nodes by X += U dt
// (dt = 1) after each, and completes them with send_positions(X) instead of send_velocities().
// Peer k's nodes occupy [node_offset(k), node_offset(k) + nodes) in the concatenated arrays.
// Coupling failures throw CouplerError after telling every peer (error frame), so all stop.
// One side object belongs to one thread at a time (its ZeroMQ sockets do).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>
#include <zmq.hpp>

#include "coupler/channel.hpp"
#include "coupler/frame_pool.hpp"
#include "coupler/halo.hpp"
#include "coupler/handshake.hpp"
#include "coupler/options.hpp"
#include "coupler/shared_segment.hpp"
#include "coupler/state.hpp"
#include "coupler/zap_guard.hpp"

namespace dld::coupler {

struct FluidConfig {
  SceneIdentity scene;
  /// One endpoint per membrane peer, in peer order (see peer_endpoints()). The fluid binds them.
  std::vector<std::string> endpoints;
  /// Expected node count of every cell (total_cells entries), or empty to accept the peers'.
  std::vector<std::uint32_t> cell_nodes;
  Options options;
};

class FluidSide {
 public:
  /// With a context of its own (ipc, tcp).
  explicit FluidSide(FluidConfig config);
  /// With the caller's context: needed for inproc, where both sides must share one.
  FluidSide(FluidConfig config, zmq::context_t& context);
  ~FluidSide();
  FluidSide(const FluidSide&) = delete;
  FluidSide& operator=(const FluidSide&) = delete;

  /// The endpoints as bound (a tcp port "*" resolved), in peer order.
  std::vector<std::string> endpoints() const;
  /// With CURVE: every client turned away so far (also logged), one line each.
  std::vector<std::string> refused_clients() const {
    return zap_ ? zap_->refusals() : std::vector<std::string>{};
  }

  /// The DLD cell's periodicity [lattice lengths], for the contact halo the peers may ask for
  /// (coupler/halo.hpp); before initialize(). Without it a peer asking for a halo is refused.
  void set_periodic_box(const PeriodicBox& box) { box_ = box; }
  void initialize();
  /// Waits for step step() from every peer. False when all peers sent shutdown instead.
  [[nodiscard]] bool receive();
  /// Concatenated node positions and forces of the received step: 3 x node_count() doubles,
  /// node-major (x0 y0 z0 x1 ...). Valid until send_velocities(). With one peer they point into
  /// the received frame or the shared segment (no copy); with several, into one concatenated
  /// array.
  std::span<const double> positions() const;
  std::span<const double> forces() const;
  /// Steps the received frames cover (the same from every peer): 1, or n > 1 held steps.
  std::uint64_t held_steps() const { return held_steps_; }
  /// Velocities for exactly the received nodes (3 x node_count()); completes the step.
  void send_velocities(std::span<const double> velocities);
  /// The nodes' positions after the held_steps() steps (3 x node_count()); completes them.
  void send_positions(std::span<const double> positions);
  /// Where to put the velocities to save a copy: with one peer on a shared-memory link this is
  /// the segment itself, and send_velocities(velocities_buffer()) copies nothing. 3 x
  /// node_count() doubles, the same memory every step, written between receive() and
  /// send_velocities().
  std::span<double> velocities_buffer();
  /// Ends the run: peers still running get a shutdown frame. Closes the sockets.
  void finalize();
  /// Stops the run because of an error of the fluid program: every peer receives `message` and
  /// stops naming the fluid and the step. The side is failed afterwards.
  void abort(std::string_view message) noexcept;

  State state() const { return state_; }
  /// The step the next receive() expects (or the received one, until send_velocities()).
  std::uint64_t step() const { return step_; }
  std::size_t peer_count() const { return peers_.size(); }
  std::size_t node_count() const { return positions_.size() / 3; }
  std::size_t node_offset(std::size_t peer) const { return peers_[peer].first_node; }
  /// True once initialized if this peer's node arrays go through shared memory.
  bool shared_memory(std::size_t peer) const { return peers_[peer].segment.mapped(); }
  /// Node count of every cell over all peers, in global cell order (after initialize()).
  std::span<const std::uint32_t> cell_nodes() const { return cell_nodes_; }
  /// Triangle count of every cell (0: the peer sent no surface), in global cell order.
  std::span<const std::uint32_t> cell_faces() const { return cell_faces_; }
  /// The triangles of all cells, 3 node indices local to their cell, in global cell order.
  std::span<const std::uint32_t> faces() const { return faces_; }
  /// The contact halo width served [lattice lengths] (0: none); after initialize().
  double contact_halo() const { return halo_; }
  /// Halo cells and bytes sent over all peers and steps so far (for the cost per step).
  std::uint64_t halo_cells_sent() const { return halo_cells_sent_; }
  std::uint64_t halo_bytes_sent() const { return halo_bytes_sent_; }
  /// "membrane 'membrane-1'" once its hello arrived, else "membrane peer 1".
  const std::string& peer_label(std::size_t peer) const { return peers_[peer].label; }

 private:
  struct Peer {
    std::unique_ptr<Channel> channel;
    std::string label;
    Handshake hello;
    std::size_t first_node = 0;
    std::size_t nodes = 0;
    bool shut_down = false;
    std::uint64_t held_steps = 1;  // steps its last frame covers
    zmq::message_t last_frame;     // kept so that positions()/forces() may point into it
    SharedSegment segment;         // ipc data path offered by the peer and accepted
  };

  void open(zmq::context_t& context);
  void receive_hellos();
  void check_hellos();
  void map_segments();
  void check_halo_widths();
  void receive_start_positions();
  /// Sends each peer the halo for `step` from all nodes at `positions` (3 x node_count()).
  void send_halos(std::span<const double> positions, std::uint64_t step);
  bool receive_steps();
  void accept_frame(std::size_t k, zmq::message_t frame);
  /// Every peer asked for the same number of held steps: sets held_steps_, else throws.
  void agree_on_held_steps();
  /// Sends peer k its velocities (n = 1) or positions frame from `values`.
  void send_nodes(Peer& peer, std::span<const double> values, bool positions);
  /// Indices of peers for which a frame is waiting, within the deadline; empty on timeout.
  std::vector<std::size_t> poll(const std::vector<std::size_t>& pending,
                                std::chrono::steady_clock::time_point deadline);
  void broadcast_error(std::string_view message) noexcept;
  /// Runs `body`; on CouplerError tells every peer, marks the side failed and rethrows.
  template <class Body>
  auto guarded(Body&& body);

  FluidConfig config_;
  std::unique_ptr<zmq::context_t> own_context_;  // declared before peers_: sockets close first
  std::unique_ptr<ZapGuard> zap_;                // with CURVE: admits the listed clients only
  std::vector<Peer> peers_;
  State state_ = State::created;
  std::uint64_t step_ = 0;
  std::uint64_t held_steps_ = 1;  // steps the received frames cover
  std::vector<std::uint32_t> cell_nodes_, cell_faces_, faces_;
  std::vector<double> positions_;  // concatenation target when the frames cannot be viewed
  std::vector<double> forces_;
  std::span<const double> positions_view_;
  std::span<const double> forces_view_;
  std::vector<double> velocities_;  // velocities_buffer() when it cannot be the segment
  FramePool pool_;                  // velocity frames
  PeriodicBox box_;
  double halo_ = 0;                           // contact halo width served, 0: none
  std::vector<std::uint32_t> first_cell_;     // peer k owns cells [first_cell_[k], [k + 1])
  std::vector<std::size_t> cell_first_node_;  // first node of every cell
  std::vector<double> next_positions_;        // x + u: where the halo's nodes are next step
  std::uint64_t halo_cells_sent_ = 0, halo_bytes_sent_ = 0;
};

}  // namespace dld::coupler
