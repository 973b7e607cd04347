// SPDX-License-Identifier: MIT
// The contact halo (coupler/halo.hpp): which cells the fluid sends each peer, and the frame's
// codec and checks.
#include "coupler/halo.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "coupler/error.hpp"

namespace dld::coupler {
namespace {

const PeriodicBox kBox{40.0, 7.5};  // lattice lengths: lambda, shift

/// Cells of two nodes each: the corners of a box of side 2 at `corner`.
std::vector<double> cells_at(const std::vector<std::array<double, 3>>& corners) {
  std::vector<double> x;
  for (const auto& c : corners) x.insert(x.end(), {c[0], c[1], c[2], c[0] + 2, c[1] + 2, c[2] + 2});
  return x;
}

TEST(Halo, PicksTheCellsNearAPeersOwnIncludingPeriodicImages) {
  // Peer 0 owns cell 0 at x 37..39; cell 1 sits across the shifted x face (its image at
  // x + lambda, y + shift is 1.5 away), cell 2 two boxes on in unwrapped x but at the same place
  // (0.5 away), cell 3 far.
  const auto x = cells_at({{37, 10, 1}, {0.5, 2.5, 1}, {39.5 + 80, 10 + 15, 1}, {20, 30, 1}});
  const std::vector<std::uint32_t> nodes{2, 2, 2, 2}, first{0, 1, 4};
  auto h = select_halos(x, nodes, first, 1.0, kBox);
  EXPECT_EQ(h[0], (std::vector<std::uint32_t>{2}));  // cell 1 is 1.5 away: outside width 1
  h = select_halos(x, nodes, first, 2.0, kBox);
  EXPECT_EQ(h[0], (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(h[1], (std::vector<std::uint32_t>{0}));  // peer 1 sees peer 0's cell, never its own
  // Without the y shift of the x face, cell 1 is 7.5 further away.
  h = select_halos(x, nodes, first, 2.0, {40.0, 0.0});
  EXPECT_EQ(h[0], (std::vector<std::uint32_t>{}));
}

TEST(Halo, FrameRoundTripAndChecks) {
  const auto x = cells_at({{1, 2, 3}, {4, 5, 6}, {7, 8, 9}});
  const std::vector<std::uint32_t> nodes{2, 2, 2}, cells{0, 2};
  const std::vector<std::size_t> first_node{0, 2, 4};
  const Link link{"membrane 'm-1'", "fluid"};
  const zmq::message_t frame = encode_halo(5, cells, nodes, first_node, x);
  const FrameHeader header = read_header(frame, link, 5);
  const Halo h = decode_halo(frame, header, 1, 2, 3, link);
  EXPECT_EQ(h.cells, cells);
  EXPECT_EQ(h.nodes, (std::vector<std::uint32_t>{2, 2}));
  std::vector<double> expected(x.begin(), x.begin() + 6);
  expected.insert(expected.end(), x.begin() + 12, x.end());
  EXPECT_EQ(h.positions, expected);
  // A cell the receiver owns, more cells than exist, a non-finite position: each named.
  const auto message = [&](std::uint32_t own_first, std::uint32_t total) {
    try {
      decode_halo(frame, header, own_first, own_first + 1, total, link);
    } catch (const CouplerError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message(2, 3).find("field 'cells[1]'"), std::string::npos) << message(2, 3);
  EXPECT_NE(message(1, 1).find("field 'cell_count'"), std::string::npos) << message(1, 1);
  auto bad = x;
  bad[13] = std::numeric_limits<double>::quiet_NaN();
  const zmq::message_t nan = encode_halo(5, cells, nodes, first_node, bad);
  EXPECT_THROW(decode_halo(nan, read_header(nan, link, 5), 1, 2, 3, link), CouplerError);
}

}  // namespace
}  // namespace dld::coupler
