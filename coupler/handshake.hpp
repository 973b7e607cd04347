// SPDX-License-Identifier: MIT
// The handshake record carried by hello (membrane -> fluid) and welcome (fluid -> membrane), and
// the comparison that stops a run whose two sides were started for different scenes.
#pragma once
#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include <zmq.hpp>

#include "coupler/frame.hpp"

namespace dld::coupler {

/// One value both sides must agree on, named by the program that hands it over (e.g. "dt_s").
/// The coupler compares values of the same name and knows nothing of what they mean.
struct AgreedValue {
  std::string name;      ///< printable ASCII, at most kMaxValueName bytes
  double value = 0;      ///< finite
  double tolerance = 0;  ///< relative: the two sides agree when |a - b| <= tol max(|a|, |b|)
};

/// What both sides must agree on: the coupler's own counts and the programs' named values.
struct SceneIdentity {
  std::string scene_hash;           ///< identity of the resolved scene (e.g. a hash of its TOML)
  std::vector<AgreedValue> agreed;  ///< the programs' values (units, geometry, ...), in order
  std::uint64_t start_step = 0;     ///< number of the first exchanged step (non-zero on restart)
  std::uint32_t total_cells = 0;    ///< cells over all membrane processes

  /// The value named `name`, or nothing.
  const AgreedValue* find(std::string_view name) const {
    for (const AgreedValue& v : agreed)
      if (v.name == name) return &v;
    return nullptr;
  }
};

/// One side's handshake record. For a hello, the membrane's own cells; for a welcome, what the
/// fluid expects of that peer (same cells, same place).
struct Handshake {
  SceneIdentity scene;
  std::string side_name;                  ///< "fluid", "membrane-0", ...
  std::uint32_t peer_index = 0;           ///< which of the fluid's endpoints this peer uses
  std::uint32_t peer_count = 1;           ///< membrane processes in the run
  std::uint32_t first_cell = 0;           ///< global index of this peer's first cell
  std::vector<std::uint32_t> cell_nodes;  ///< node count of every cell the peer owns, in order
  /// Triangle count of every owned cell (0: the cell has no surface, e.g. a tracer). Empty means
  /// all zero. The fluid needs the surfaces for the inside/outside viscosity field.
  std::vector<std::uint32_t> cell_faces;
  /// The triangles, three node indices local to their cell, cell after cell (3 x sum(cell_faces)).
  std::vector<std::uint32_t> faces;
  /// Shared-memory data path (ipc): in a hello, the segment the membrane offers; in a welcome,
  /// the same name if the fluid mapped it, empty if it declines. Empty: frames carry the data.
  std::string shared_memory;
  /// Contact halo width [lattice lengths]: in a hello, how near other processes' cells must come
  /// for this peer's contact to need their nodes (0: never, e.g. one process or no cell-cell
  /// contact); in a welcome, the width the fluid serves (coupler/halo.hpp).
  double contact_halo = 0;
};

inline constexpr std::size_t kHandshakeFixedBytes = 60;
inline constexpr std::size_t kMaxNameBytes = 256;
/// Named values of one record at most, and bytes of one name at most.
inline constexpr std::uint32_t kMaxAgreedValues = 64;
inline constexpr std::size_t kMaxValueName = 64;
/// Nodes of one cell at most: a 2000-face cell has 1002; this leaves room for any mesh.
inline constexpr std::uint32_t kMaxCellNodes = 1'000'000;

zmq::message_t encode_handshake(FrameType type, const Handshake& record);
/// Decodes the payload of a hello or welcome; a short or inconsistent record is a malformed frame.
Handshake decode_handshake(const zmq::message_t& frame, const FrameHeader& header,
                           const Link& link);

/// The one-line mismatch message, always oriented fluid first:
/// "handshake: field 'dt_s': fluid has 2.1e-08, membrane 'membrane-0' has 2.2e-08".
template <class A, class B>
std::string mismatch(std::string_view field, const A& fluid_value, std::string_view membrane,
                     const B& membrane_value) {
  return fmt::format("handshake: field '{}': fluid has {}, {} has {}", field, fluid_value, membrane,
                     membrane_value);
}

/// The first field of the scene identity on which the two sides disagree, as a mismatch message.
std::optional<std::string> scene_mismatch(const SceneIdentity& fluid, const SceneIdentity& membrane,
                                          std::string_view membrane_label);

/// "membrane 'membrane-0'": how messages name a membrane peer.
std::string membrane_label(std::string_view side_name);

}  // namespace dld::coupler
