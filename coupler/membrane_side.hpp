// SPDX-License-Identifier: MIT
// A membrane program's end of the coupling: one peer of the fluid, owning some of the cells.
//
// Call order (checked; a wrong order throws std::logic_error):
//   MembraneSide membrane(config);        // connects to the fluid's endpoint for this peer
//   membrane.initialize();                // hello out, welcome in, handshake checked
//   for (...) {
//     ... forces F at positions X of the owned nodes (cells in order, nodes of a cell in order) ...
//     if (!membrane.advance(X, F, U)) break;  // U: velocities at X; false: the fluid ended the run
//     ... X += U dt ...
//   }
// With forces held for n > 1 steps ([coupling] force_every), advance_held(X, F, n, X') lets the
// fluid run the n steps and move the nodes itself (X += U dt each step); X' are their positions
// after them (docs/protocol.md, "Held steps").
//   membrane.finalize();                  // tells the fluid the run ends (if it has not ended it)
// Coupling failures throw CouplerError after telling the fluid (error frame), which stops too.
// One side object belongs to one thread at a time (its ZeroMQ sockets do).
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
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

namespace dld::coupler {

struct MembraneConfig {
  SceneIdentity scene;
  std::string endpoint;                   ///< the fluid's endpoint for this peer
  std::string name = "membrane-0";        ///< names this side in every message
  std::uint32_t peer_index = 0;           ///< which fluid endpoint this is
  std::uint32_t peer_count = 1;           ///< membrane programs in the run
  std::uint32_t first_cell = 0;           ///< global index of the first owned cell
  std::vector<std::uint32_t> cell_nodes;  ///< node count of every owned cell, in order
  Options options;
  /// Contact halo width [lattice lengths] this side's contact needs from other processes' cells
  /// (0: none); the fluid must serve the same (coupler/halo.hpp).
  double contact_halo = 0;
};

class MembraneSide {
 public:
  /// With a context of its own (ipc, tcp).
  explicit MembraneSide(MembraneConfig config);
  /// With the caller's context: needed for inproc, where both sides must share one.
  MembraneSide(MembraneConfig config, zmq::context_t& context);
  ~MembraneSide();
  MembraneSide(const MembraneSide&) = delete;
  MembraneSide& operator=(const MembraneSide&) = delete;

  /// The triangles of every owned cell (cell_faces: count per cell; faces: 3 local node indices
  /// per triangle, cell after cell), sent once in the hello for the fluid's viscosity field.
  /// Before initialize(); without it the hello says the cells have no surface.
  void set_cell_surfaces(std::vector<std::uint32_t> cell_faces, std::vector<std::uint32_t> faces);
  /// With a contact halo, `start_positions` (3 x node_count() doubles, the positions of the first
  /// step) go to the fluid, and halo() holds the other processes' cells near them on return.
  void initialize(std::span<const double> start_positions = {});
  /// With a contact halo: other processes' cells near this side's, at the positions of step()
  /// (after initialize() and after each exchange, which receives it with the velocities).
  const Halo& halo() const { return halo_; }
  /// Exchanges step step(): sends positions and forces (3 x node_count() doubles each,
  /// node-major), waits for the velocities of the same nodes and writes them to `velocities`.
  /// Returns false, writing nothing, if the fluid ended the run instead.
  [[nodiscard]] bool advance(std::span<const double> positions, std::span<const double> forces,
                             std::span<double> velocities);
  /// The same exchange without the last copy: the velocities are returned as a view into the
  /// received frame, valid until the next call; nothing if the fluid ended the run.
  [[nodiscard]] std::optional<std::span<const double>> exchange(std::span<const double> positions,
                                                                std::span<const double> forces);
  /// Steps step() to step() + n - 1 with the forces held: the fluid spreads `forces` at the
  /// nodes, advances and moves them by X += U dt (dt = 1) each step, and answers with their
  /// positions after step() + n - 1, written to `positions_after` (may be `positions`). n = 1 is
  /// advance() followed by that move. Returns false, writing nothing, if the fluid ended the run.
  [[nodiscard]] bool advance_held(std::span<const double> positions, std::span<const double> forces,
                                  std::uint64_t n, std::span<double> positions_after);
  /// Where to put positions and forces to save the first copy too: on a shared-memory link these
  /// are the segment itself, and exchange(positions_buffer(), forces_buffer()) copies nothing;
  /// on other links, staging arrays the frame is encoded from. 3 x node_count() doubles each,
  /// the same memory every step (a program may keep its node state there), written only between
  /// exchanges (after initialize()).
  std::span<double> positions_buffer();
  std::span<double> forces_buffer();
  void finalize();
  /// Stops the run because of an error of the membrane program: the fluid receives `message`, and
  /// through it every other membrane peer. The side is failed afterwards.
  void abort(std::string_view message) noexcept;

  State state() const { return state_; }
  std::uint64_t step() const { return step_; }
  std::size_t node_count() const { return nodes_; }
  /// True once initialized if node arrays go through shared memory (ipc, both sides allow it).
  bool shared_memory() const { return shared_; }
  /// "membrane 'membrane-0'".
  const std::string& label() const { return self_; }

 private:
  template <class Body>
  auto guarded(Body&& body);
  void check_welcome(const Handshake& welcome);
  void receive_halo();
  /// Sends n steps' positions and forces (n = 1: a step frame) and receives the fluid's answer:
  /// velocities (n = 1) or positions after the n steps; nothing if the fluid ended the run.
  std::optional<std::span<const double>> exchange_steps(std::span<const double> positions,
                                                        std::span<const double> forces,
                                                        std::uint64_t n);
  void send_steps(std::span<const double> positions, std::span<const double> forces,
                  std::uint64_t n);

  MembraneConfig config_;
  std::vector<std::uint32_t> cell_faces_, faces_;
  std::string self_;
  std::unique_ptr<zmq::context_t> own_context_;  // declared before channel_: socket closes first
  std::unique_ptr<Channel> channel_;
  State state_ = State::created;
  std::uint64_t step_ = 0;
  std::size_t nodes_ = 0;
  FramePool pool_;                 // step frames
  zmq::message_t reply_;           // the last velocities or positions frame, viewed by exchange()
  std::vector<double> unaligned_;  // copy target if a frame's doubles are not aligned
  std::vector<double> staging_;    // positions_buffer() | forces_buffer() without shared memory
  SharedSegment segment_;  // ipc data path: positions | forces | velocities, 24 N bytes each
  bool shared_ = false;    // the fluid accepted the segment
  Halo halo_;
};

}  // namespace dld::coupler
