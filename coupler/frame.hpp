// SPDX-License-Identifier: MIT
// Frame codec: the byte layout of every message of the protocol (docs/protocol.md, "Frames").
// A frame is one ZeroMQ message: a 24-byte header followed by a payload, all little-endian.
#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <zmq.hpp>

namespace dld::coupler {

class FramePool;

static_assert(std::endian::native == std::endian::little,
              "the frame codec copies doubles and integers as they lie in memory");

inline constexpr std::uint32_t kMagic = 0x43444C44;  ///< bytes 'D' 'L' 'D' 'C'
/// 2: cell surfaces in the handshake; 3: named values to agree on instead of fixed fields;
/// 4: the contact halo (handshake field, start positions and halo frames). Held steps (frame types
/// 11-14) came later without a new version: only a membrane that sends them gets them answered.
inline constexpr std::uint16_t kProtocolVersion = 4;
inline constexpr std::size_t kHeaderBytes = 24;

enum class FrameType : std::uint16_t {
  hello = 1,              ///< membrane -> fluid: handshake record
  welcome = 2,            ///< fluid -> membrane: handshake record of the fluid for this peer
  step = 3,               ///< membrane -> fluid: node count, positions (N x 3), forces (N x 3)
  velocities = 4,         ///< fluid -> membrane: node count, velocities (N x 3)
  shutdown = 5,           ///< either way: the sender ends the run cleanly; empty payload
  error = 6,              ///< either way: the sender failed; payload = its one-line message (UTF-8)
  step_shared = 7,        ///< as step, the arrays in the shared segment; payload = node count
  velocities_shared = 8,  ///< as velocities, the array in the shared segment; payload = count
  start_positions = 9,    ///< membrane -> fluid, once before step 1 (halo on): count, N x 3
  halo = 10,              ///< fluid -> membrane (halo on): other peers' cells near its own
  held_steps = 11,        ///< membrane -> fluid: node count, step count n, positions, forces
  held_steps_shared = 12,  ///< as held_steps, the arrays in the shared segment: count, n
  positions = 13,          ///< fluid -> membrane: node count, positions after the n held steps
  positions_shared = 14,   ///< as positions, the array in the shared segment's positions region
};
inline constexpr std::uint16_t kLastFrameType = 14;
std::string_view to_string(FrameType type);

struct FrameHeader {
  std::uint16_t version = kProtocolVersion;
  FrameType type = FrameType::error;
  std::uint64_t step = 0;
  std::uint64_t payload_bytes = 0;
};

/// Who is talking to whom, for error messages: "fluid", "membrane 'membrane-0'".
struct Link {
  std::string self;
  std::string peer;
};

/// Payload sizes, so senders allocate once and receivers check counts.
constexpr std::size_t step_payload_bytes(std::size_t nodes) {
  return 8 + std::size_t{48} * nodes;  // count, positions, forces
}
constexpr std::size_t velocities_payload_bytes(std::size_t nodes) {
  return 8 + std::size_t{24} * nodes;  // count, velocities
}
constexpr std::size_t held_steps_payload_bytes(std::size_t nodes) {
  return 16 + std::size_t{48} * nodes;  // count, step count, positions, forces
}
/// The most steps one held_steps frame may ask for (a sanity bound on a peer's value).
inline constexpr std::uint64_t kMostHeldSteps = 1000000;

/// Writes the 24-byte header at `at`.
void write_header(std::byte* at, FrameType type, std::uint64_t step, std::size_t payload_bytes);
/// A message of header + payload_bytes whose payload the caller fills (one allocation, no copy).
zmq::message_t make_frame(FrameType type, std::uint64_t step, std::size_t payload_bytes);
std::byte* payload(zmq::message_t& frame);
const std::byte* payload(const zmq::message_t& frame);

/// positions and forces: 3 N doubles each, node-major (x0 y0 z0 x1 ...). With a pool, the frame
/// reuses one of its buffers instead of a fresh allocation.
zmq::message_t encode_step(std::uint64_t step, std::span<const double> positions,
                           std::span<const double> forces, FramePool* pool = nullptr);
zmq::message_t encode_velocities(std::uint64_t step, std::span<const double> velocities,
                                 FramePool* pool = nullptr);
/// n steps of held forces (the fluid moves the nodes by X += U dt itself and answers with the
/// positions after step + n): as encode_step with the step count after the node count.
zmq::message_t encode_held_steps(std::uint64_t step, std::uint64_t n,
                                 std::span<const double> positions, std::span<const double> forces,
                                 FramePool* pool = nullptr);
/// The shared-memory form: node count and step count only.
zmq::message_t encode_held_steps_shared(std::uint64_t step, std::size_t nodes, std::uint64_t n);
/// The fluid's answer to held_steps: the positions after them (3 N doubles).
zmq::message_t encode_positions(std::uint64_t step, std::span<const double> positions,
                                FramePool* pool = nullptr);
/// The positions a membrane starts from (3 N doubles), sent once before its first step when the
/// contact halo is on: count, positions, laid out as a velocities frame.
zmq::message_t encode_start_positions(std::uint64_t step, std::span<const double> positions);
/// Step and velocities frames of the shared-memory data path: the header and the node count only.
zmq::message_t encode_count(FrameType type, std::uint64_t step, std::size_t nodes);
zmq::message_t encode_shutdown(std::uint64_t step);
zmq::message_t encode_error(std::uint64_t step, std::string_view message);

/// Reads and checks the header of a received frame: size, magic, version, known type, payload
/// length. `at_step` is the step the receiver is at, for the message. Throws CouplerError:
/// "fluid: malformed frame from membrane 'm-0' at step 4: field 'magic': expected ..., got ...".
FrameHeader read_header(const zmq::message_t& frame, const Link& link, std::uint64_t at_step);

/// Node arrays (3 N doubles each) a frame carries after its node count: a step frame positions
/// and forces, a velocities frame the velocities, a shared-memory frame none (they are in the
/// segment, coupler/shared_segment.hpp).
inline constexpr int kStepFrameArrays = 2;
inline constexpr int kVelocitiesFrameArrays = 1;
inline constexpr int kSharedFrameArrays = 0;

/// Checks a node payload (step or velocities): its node count equals `nodes` and its length
/// matches; returns the bytes of the `arrays` arrays of 3 N doubles that follow the count
/// (`arrays` = 0 for the shared-memory frames, which carry the count only).
const std::byte* read_nodes(const zmq::message_t& frame, const FrameHeader& header,
                            std::size_t nodes, int arrays, const Link& link);

/// A held_steps or held_steps_shared frame's step count n (1 <= n <= kMostHeldSteps) and the
/// bytes of its arrays (as read_nodes; `arrays` = 2, or 0 for the shared form).
struct HeldSteps {
  std::uint64_t steps = 1;
  const std::byte* data = nullptr;
};
HeldSteps read_held_steps(const zmq::message_t& frame, const FrameHeader& header, std::size_t nodes,
                          int arrays, const Link& link);

/// The text of an error frame, cut at 4 KiB and with line breaks turned into spaces so it stays
/// one line in the receiver's message.
std::string read_error_text(const zmq::message_t& frame, const FrameHeader& header);

/// Throws CouplerError "<self>: malformed frame from <peer> at step <n>: field '<f>': <detail>".
[[noreturn]] void throw_malformed(const Link& link, std::uint64_t step, std::string_view field,
                                  std::string_view detail);

/// A data frame of a running step (not shutdown or error, which the caller handled): its type is
/// `expected` and its step `step`, else throw_malformed naming "type" or "step".
void require_data_frame(const FrameHeader& header, FrameType expected, std::uint64_t step,
                        const Link& link);

/// Refuses (throw_malformed, naming `field` and the first bad node) a node array of 3 x `nodes`
/// doubles at `data` (any alignment) holding a NaN or an infinity: a peer's non-finite values
/// would otherwise spread through the lattice and into its checkpoints.
void require_finite(const std::byte* data, std::size_t nodes, std::string_view field,
                    const Link& link, std::uint64_t step);

}  // namespace dld::coupler
