// SPDX-License-Identifier: MIT
// The contact halo (docs/protocol.md, "The contact halo"): with cells split over several membrane
// processes, each process must see the nodes of other processes' cells near its own, or cells of
// different processes would pass through each other. The fluid gathers every node each step, so
// it picks, for each peer, the other peers' cells whose bounding box comes within the halo width
// of one of the peer's own (nearest periodic image: x period lambda with a y shift, y period
// lambda) and sends their nodes after the velocities. All lengths in lattice units.
#pragma once
#include <cstdint>
#include <span>
#include <vector>
#include <zmq.hpp>

#include "coupler/frame.hpp"

namespace dld::coupler {

/// The periodic box of the DLD cell [lattice lengths]: leaving at x = lambda at height y
/// re-enters at x = 0 at y - shift; y is periodic with period lambda.
struct PeriodicBox {
  double lambda = 0;
  double shift = 0;
};

/// Other processes' cells near a peer's own, at the step the peer computes its next forces.
struct Halo {
  std::vector<std::uint32_t> cells;  ///< global cell indices, ascending
  std::vector<std::uint32_t> nodes;  ///< node count of each of those cells
  std::vector<double> positions;     ///< their nodes, node-major x, y, z, cell after cell
};

/// For every peer k (owning cells [first_cell[k], first_cell[k + 1])), the cells of other peers
/// whose axis-aligned bounding box (nearest periodic image) lies within `width` of the box of one
/// of k's cells. `positions`: all nodes, cells in global order, `cell_nodes` nodes each.
std::vector<std::vector<std::uint32_t>> select_halos(std::span<const double> positions,
                                                     std::span<const std::uint32_t> cell_nodes,
                                                     std::span<const std::uint32_t> first_cell,
                                                     double width, const PeriodicBox& box);

/// Halo frame: u64 cell count G, G u32 cell indices, G u32 node counts, then the nodes' positions
/// (3 per node, doubles). `cells` ascending; `first_node[c]` is cell c's first node in
/// `positions` (all cells), `cell_nodes[c]` its node count.
zmq::message_t encode_halo(std::uint64_t step, std::span<const std::uint32_t> cells,
                           std::span<const std::uint32_t> cell_nodes,
                           std::span<const std::size_t> first_node,
                           std::span<const double> positions);
/// Decodes and checks a halo frame for a side owning cells [own_first, own_last) of
/// `total_cells`: counts within bounds and matching the length, cells ascending, none owned by
/// the receiver, every position finite. Throws CouplerError naming the field.
Halo decode_halo(const zmq::message_t& frame, const FrameHeader& header, std::uint32_t own_first,
                 std::uint32_t own_last, std::uint32_t total_cells, const Link& link);

}  // namespace dld::coupler
