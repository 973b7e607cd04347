// SPDX-License-Identifier: MIT
#include "coupler/frame.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "coupler/error.hpp"
#include "coupler/frame_pool.hpp"

namespace dld::coupler {

namespace {

// Fixed-width little-endian fields are copied with memcpy: received bytes need not be aligned.
template <class T>
void put(std::byte* at, T value) {
  std::memcpy(at, &value, sizeof(T));
}
template <class T>
T get(const std::byte* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  return value;
}

constexpr std::size_t kMaxErrorText = 4096;

}  // namespace

std::string_view to_string(FrameType type) {
  switch (type) {
    case FrameType::hello:
      return "hello";
    case FrameType::welcome:
      return "welcome";
    case FrameType::step:
      return "step";
    case FrameType::velocities:
      return "velocities";
    case FrameType::shutdown:
      return "shutdown";
    case FrameType::error:
      return "error";
    case FrameType::step_shared:
      return "step_shared";
    case FrameType::velocities_shared:
      return "velocities_shared";
    case FrameType::start_positions:
      return "start_positions";
    case FrameType::halo:
      return "halo";
    case FrameType::held_steps:
      return "held_steps";
    case FrameType::held_steps_shared:
      return "held_steps_shared";
    case FrameType::positions:
      return "positions";
    case FrameType::positions_shared:
      return "positions_shared";
  }
  return "unknown";
}

void write_header(std::byte* at, FrameType type, std::uint64_t step, std::size_t payload_bytes) {
  put(at + 0, kMagic);
  put(at + 4, kProtocolVersion);
  put(at + 6, static_cast<std::uint16_t>(type));
  put(at + 8, step);
  put(at + 16, static_cast<std::uint64_t>(payload_bytes));
}

zmq::message_t make_frame(FrameType type, std::uint64_t step, std::size_t payload_bytes) {
  zmq::message_t frame(kHeaderBytes + payload_bytes);
  write_header(static_cast<std::byte*>(frame.data()), type, step, payload_bytes);
  return frame;
}

std::byte* payload(zmq::message_t& frame) {
  return static_cast<std::byte*>(frame.data()) + kHeaderBytes;
}
const std::byte* payload(const zmq::message_t& frame) {
  return static_cast<const std::byte*>(frame.data()) + kHeaderBytes;
}

zmq::message_t encode_step(std::uint64_t step, std::span<const double> positions,
                           std::span<const double> forces, FramePool* pool) {
  assert(positions.size() == forces.size() && positions.size() % 3 == 0);
  const std::size_t nodes = positions.size() / 3;
  zmq::message_t frame = pool ? pool->make(FrameType::step, step, step_payload_bytes(nodes))
                              : make_frame(FrameType::step, step, step_payload_bytes(nodes));
  std::byte* at = payload(frame);
  put(at, static_cast<std::uint64_t>(nodes));
  std::memcpy(at + 8, positions.data(), positions.size_bytes());
  std::memcpy(at + 8 + positions.size_bytes(), forces.data(), forces.size_bytes());
  return frame;
}

namespace {
zmq::message_t encode_array(FrameType type, std::uint64_t step, std::span<const double> values,
                            FramePool* pool) {
  assert(values.size() % 3 == 0);
  const std::size_t nodes = values.size() / 3;
  const std::size_t bytes = velocities_payload_bytes(nodes);
  zmq::message_t frame = pool ? pool->make(type, step, bytes) : make_frame(type, step, bytes);
  std::byte* at = payload(frame);
  put(at, static_cast<std::uint64_t>(nodes));
  std::memcpy(at + 8, values.data(), values.size_bytes());
  return frame;
}
}  // namespace

zmq::message_t encode_velocities(std::uint64_t step, std::span<const double> velocities,
                                 FramePool* pool) {
  return encode_array(FrameType::velocities, step, velocities, pool);
}

zmq::message_t encode_positions(std::uint64_t step, std::span<const double> positions,
                                FramePool* pool) {
  return encode_array(FrameType::positions, step, positions, pool);
}

zmq::message_t encode_held_steps(std::uint64_t step, std::uint64_t n,
                                 std::span<const double> positions, std::span<const double> forces,
                                 FramePool* pool) {
  assert(positions.size() == forces.size() && positions.size() % 3 == 0);
  const std::size_t nodes = positions.size() / 3;
  const std::size_t bytes = held_steps_payload_bytes(nodes);
  zmq::message_t frame = pool ? pool->make(FrameType::held_steps, step, bytes)
                              : make_frame(FrameType::held_steps, step, bytes);
  std::byte* at = payload(frame);
  put(at, static_cast<std::uint64_t>(nodes));
  put(at + 8, n);
  std::memcpy(at + 16, positions.data(), positions.size_bytes());
  std::memcpy(at + 16 + positions.size_bytes(), forces.data(), forces.size_bytes());
  return frame;
}

zmq::message_t encode_held_steps_shared(std::uint64_t step, std::size_t nodes, std::uint64_t n) {
  zmq::message_t frame = make_frame(FrameType::held_steps_shared, step, 16);
  put(payload(frame), static_cast<std::uint64_t>(nodes));
  put(payload(frame) + 8, n);
  return frame;
}

zmq::message_t encode_start_positions(std::uint64_t step, std::span<const double> positions) {
  return encode_array(FrameType::start_positions, step, positions, nullptr);
}

zmq::message_t encode_count(FrameType type, std::uint64_t step, std::size_t nodes) {
  zmq::message_t frame = make_frame(type, step, 8);
  put(payload(frame), static_cast<std::uint64_t>(nodes));
  return frame;
}

zmq::message_t encode_shutdown(std::uint64_t step) {
  return make_frame(FrameType::shutdown, step, 0);
}

zmq::message_t encode_error(std::uint64_t step, std::string_view message) {
  message = message.substr(0, kMaxErrorText);
  zmq::message_t frame = make_frame(FrameType::error, step, message.size());
  std::memcpy(payload(frame), message.data(), message.size());
  return frame;
}

void throw_malformed(const Link& link, std::uint64_t step, std::string_view field,
                     std::string_view detail) {
  throw CouplerError(fmt::format("{}: malformed frame from {} at step {}: field '{}': {}",
                                 link.self, link.peer, step, field, detail));
}

void require_data_frame(const FrameHeader& header, FrameType expected, std::uint64_t step,
                        const Link& link) {
  if (header.type != expected) {
    throw_malformed(link, step, "type",
                    fmt::format("expected {}, shutdown or error, got {}", to_string(expected),
                                to_string(header.type)));
  }
  if (header.step != step) {
    throw_malformed(link, step, "step", fmt::format("expected {}, got {}", step, header.step));
  }
}

FrameHeader read_header(const zmq::message_t& frame, const Link& link, std::uint64_t at_step) {
  if (frame.size() < kHeaderBytes) {
    throw_malformed(link, at_step, "header",
                    fmt::format("frame of {} bytes is shorter than the {}-byte header",
                                frame.size(), kHeaderBytes));
  }
  const auto* at = static_cast<const std::byte*>(frame.data());
  const auto magic = get<std::uint32_t>(at);
  if (magic != kMagic) {
    throw_malformed(link, at_step, "magic",
                    fmt::format("expected {:#010x} (\"DLDC\"), got {:#010x}", kMagic, magic));
  }
  FrameHeader header;
  header.version = get<std::uint16_t>(at + 4);
  if (header.version != kProtocolVersion) {
    throw_malformed(link, at_step, "version",
                    fmt::format("expected {}, got {}", kProtocolVersion, header.version));
  }
  const auto type = get<std::uint16_t>(at + 6);
  if (type < static_cast<std::uint16_t>(FrameType::hello) || type > kLastFrameType) {
    throw_malformed(link, at_step, "type", fmt::format("unknown frame type {}", type));
  }
  header.type = static_cast<FrameType>(type);
  header.step = get<std::uint64_t>(at + 8);
  header.payload_bytes = get<std::uint64_t>(at + 16);
  if (header.payload_bytes != frame.size() - kHeaderBytes) {
    throw_malformed(
        link, at_step, "payload_bytes",
        fmt::format("header announces {} bytes but the {} frame carries {}", header.payload_bytes,
                    to_string(header.type), frame.size() - kHeaderBytes));
  }
  return header;
}

namespace {

/// The node arrays of a payload that opens with `counts` u64 fields, the first the node count:
/// checks that count and the payload's length; returns the bytes after the counts.
const std::byte* read_counted_nodes(const zmq::message_t& frame, const FrameHeader& header,
                                    std::size_t nodes, int arrays, int counts, const Link& link) {
  const std::byte* at = payload(frame);
  const std::size_t head = 8 * static_cast<std::size_t>(counts);
  if (header.payload_bytes < head) {
    throw_malformed(link, header.step, "node_count",
                    fmt::format("{} frame too short to hold the node count{}",
                                to_string(header.type), counts > 1 ? " and step count" : ""));
  }
  const auto count = get<std::uint64_t>(at);
  if (count != nodes) {
    throw_malformed(link, header.step, "node_count",
                    fmt::format("expected {} nodes, got {}", nodes, count));
  }
  const std::size_t expected = head + static_cast<std::size_t>(arrays) * 3 * 8 * nodes;
  if (header.payload_bytes != expected) {
    throw_malformed(link, header.step, "payload_bytes",
                    fmt::format("{} nodes need {} bytes in a {} frame, got {}", nodes, expected,
                                to_string(header.type), header.payload_bytes));
  }
  return at + head;
}

}  // namespace

const std::byte* read_nodes(const zmq::message_t& frame, const FrameHeader& header,
                            std::size_t nodes, int arrays, const Link& link) {
  return read_counted_nodes(frame, header, nodes, arrays, 1, link);
}

HeldSteps read_held_steps(const zmq::message_t& frame, const FrameHeader& header, std::size_t nodes,
                          int arrays, const Link& link) {
  const std::byte* data = read_counted_nodes(frame, header, nodes, arrays, 2, link);
  const auto n = get<std::uint64_t>(payload(frame) + 8);
  if (n < 1 || n > kMostHeldSteps) {
    throw_malformed(link, header.step, "held_steps",
                    fmt::format("expected 1 to {} steps, got {}", kMostHeldSteps, n));
  }
  return {n, data};
}

void require_finite(const std::byte* data, std::size_t nodes, std::string_view field,
                    const Link& link, std::uint64_t step) {
  constexpr std::size_t kChunk = 512;  // values checked per copy (the array may be unaligned)
  double v[kChunk];
  for (std::size_t first = 0; first < 3 * nodes; first += kChunk) {
    const std::size_t n = std::min(kChunk, 3 * nodes - first);
    std::memcpy(v, data + first * sizeof(double), n * sizeof(double));
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) finite &= std::isfinite(v[i]);
    if (finite) continue;
    for (std::size_t i = 0; i < n; ++i) {
      if (!std::isfinite(v[i])) {
        throw_malformed(link, step, field,
                        fmt::format("node {} has a non-finite value ({})", (first + i) / 3, v[i]));
      }
    }
  }
}

std::string read_error_text(const zmq::message_t& frame, const FrameHeader& header) {
  const auto* at = reinterpret_cast<const char*>(payload(frame));
  std::string text(at, std::min<std::size_t>(header.payload_bytes, kMaxErrorText));
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  if (text.empty()) {
    text = "(no message)";
  }
  return text;
}

}  // namespace dld::coupler
