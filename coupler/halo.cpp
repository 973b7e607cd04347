// SPDX-License-Identifier: MIT
#include "coupler/halo.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "coupler/handshake.hpp"

namespace dld::coupler {

namespace {

struct Bounds {
  std::array<double, 3> lo{}, hi{};
  double centre(int a) const { return 0.5 * (lo[a] + hi[a]); }
};

std::vector<Bounds> cell_bounds(std::span<const double> x, std::span<const std::uint32_t> nodes) {
  std::vector<Bounds> b(nodes.size());
  std::size_t at = 0;
  for (std::size_t c = 0; c < nodes.size(); ++c) {
    for (int a = 0; a < 3; ++a) b[c].lo[a] = b[c].hi[a] = x[3 * at + a];
    for (std::size_t i = at; i < at + nodes[c]; ++i) {
      for (int a = 0; a < 3; ++a) {
        b[c].lo[a] = std::min(b[c].lo[a], x[3 * i + a]);
        b[c].hi[a] = std::max(b[c].hi[a], x[3 * i + a]);
      }
    }
    at += nodes[c];
  }
  return b;
}

double gap2(const Bounds& a, const Bounds& b, const std::array<double, 3>& t) {
  double g2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double g = std::max({0.0, a.lo[k] - (b.hi[k] + t[k]), (b.lo[k] + t[k]) - a.hi[k]});
    g2 += g * g;
  }
  return g2;
}

// The images of b nearest to a: the whole translations kx (lambda, shift, 0) + ky (0, lambda, 0)
// around the one that brings the centres closest (cells are smaller than the box, so the 3 x 3
// around it hold the nearest image of every point of the boxes).
bool near(const Bounds& a, const Bounds& b, double width, const PeriodicBox& box) {
  const double L = box.lambda;
  const double kx0 = std::round((a.centre(0) - b.centre(0)) / L);
  for (double kx = kx0 - 1; kx <= kx0 + 1; ++kx) {
    const double ky0 = std::round((a.centre(1) - b.centre(1) - kx * box.shift) / L);
    for (double ky = ky0 - 1; ky <= ky0 + 1; ++ky) {
      if (gap2(a, b, {kx * L, kx * box.shift + ky * L, 0.0}) < width * width) return true;
    }
  }
  return false;
}

template <class T>
T get(const std::byte*& at) {
  T v;
  std::memcpy(&v, at, sizeof(T));
  at += sizeof(T);
  return v;
}

}  // namespace

std::vector<std::vector<std::uint32_t>> select_halos(std::span<const double> positions,
                                                     std::span<const std::uint32_t> cell_nodes,
                                                     std::span<const std::uint32_t> first_cell,
                                                     double width, const PeriodicBox& box) {
  const std::vector<Bounds> b = cell_bounds(positions, cell_nodes);
  const std::size_t peers = first_cell.size() - 1;
  std::vector<std::vector<std::uint32_t>> halos(peers);
  for (std::size_t k = 0; k < peers; ++k) {
    for (std::uint32_t c = 0; c < cell_nodes.size(); ++c) {
      if (c >= first_cell[k] && c < first_cell[k + 1]) continue;
      for (std::uint32_t own = first_cell[k]; own < first_cell[k + 1]; ++own) {
        if (near(b[own], b[c], width, box)) {
          halos[k].push_back(c);
          break;
        }
      }
    }
  }
  return halos;
}

zmq::message_t encode_halo(std::uint64_t step, std::span<const std::uint32_t> cells,
                           std::span<const std::uint32_t> cell_nodes,
                           std::span<const std::size_t> first_node,
                           std::span<const double> positions) {
  std::size_t nodes = 0;
  for (std::uint32_t c : cells) nodes += cell_nodes[c];
  zmq::message_t frame = make_frame(FrameType::halo, step, 8 + 8 * cells.size() + 24 * nodes);
  std::byte* at = payload(frame);
  const std::uint64_t count = cells.size();
  std::memcpy(at, &count, 8);
  at += 8;
  std::memcpy(at, cells.data(), 4 * cells.size());
  at += 4 * cells.size();
  for (std::uint32_t c : cells) {
    std::memcpy(at, &cell_nodes[c], 4);
    at += 4;
  }
  for (std::uint32_t c : cells) {
    const std::size_t bytes = 24 * std::size_t{cell_nodes[c]};
    std::memcpy(at, positions.data() + 3 * first_node[c], bytes);
    at += bytes;
  }
  return frame;
}

Halo decode_halo(const zmq::message_t& frame, const FrameHeader& header, std::uint32_t own_first,
                 std::uint32_t own_last, std::uint32_t total_cells, const Link& link) {
  const std::byte* at = payload(frame);
  const std::uint64_t bytes = header.payload_bytes;
  if (bytes < 8) throw_malformed(link, header.step, "cell_count", "halo frame too short for it");
  const auto count = get<std::uint64_t>(at);
  if (count > total_cells || bytes < 8 + 8 * count) {
    throw_malformed(
        link, header.step, "cell_count",
        fmt::format("{} cells: expected at most {} within {} bytes", count, total_cells, bytes));
  }
  Halo h;
  h.cells.resize(count);
  h.nodes.resize(count);
  std::memcpy(h.cells.data(), at, 4 * count);
  std::memcpy(h.nodes.data(), at + 4 * count, 4 * count);
  at += 8 * count;
  std::uint64_t nodes = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint32_t c = h.cells[i];
    if (c >= total_cells || (c >= own_first && c < own_last) || (i > 0 && c <= h.cells[i - 1])) {
      throw_malformed(link, header.step, fmt::format("cells[{}]", i),
                      fmt::format("cell {}: expected ascending cells below {} outside this "
                                  "side's [{}, {})",
                                  c, total_cells, own_first, own_last));
    }
    if (h.nodes[i] == 0 || h.nodes[i] > kMaxCellNodes) {
      throw_malformed(link, header.step, fmt::format("nodes[{}]", i),
                      fmt::format("{}: expected 1..{}", h.nodes[i], kMaxCellNodes));
    }
    nodes += h.nodes[i];
  }
  if (bytes != 8 + 8 * count + 24 * nodes) {
    throw_malformed(link, header.step, "payload_bytes",
                    fmt::format("{} cells of {} nodes need {} bytes, got {}", count, nodes,
                                8 + 8 * count + 24 * nodes, bytes));
  }
  require_finite(at, nodes, "halo positions", link, header.step);
  h.positions.resize(3 * nodes);
  std::memcpy(h.positions.data(), at, 24 * nodes);
  return h;
}

}  // namespace dld::coupler
