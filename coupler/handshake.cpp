// SPDX-License-Identifier: MIT
#include "coupler/handshake.hpp"

#include <cmath>
#include <cstring>

namespace dld::coupler {

namespace {

template <class T>
void put(std::byte*& at, T value) {
  std::memcpy(at, &value, sizeof(T));
  at += sizeof(T);
}
template <class T>
T get(const std::byte*& at) {
  T value;
  std::memcpy(&value, at, sizeof(T));
  at += sizeof(T);
  return value;
}

bool same(double a, double b, double tolerance) {
  return a == b || std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

/// Bytes of the named values in a record: per value a u32 name length, the name, value, tolerance.
std::size_t values_bytes(const std::vector<AgreedValue>& values) {
  std::size_t n = 0;
  for (const AgreedValue& v : values) n += 4 + v.name.size() + 16;
  return n;
}

/// Printable ASCII only: names go into every message about a field or side, and a newline or NUL
/// in one would cut or forge those lines.
void check_printable(const std::string& text, const char* field, const Link& link,
                     std::uint64_t step) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c > 0x7e) {
      throw_malformed(link, step, field,
                      fmt::format("byte {} is 0x{:02x}: expected printable ASCII", i, c));
    }
  }
}

/// The named values block of a record (`bytes` long) at `at`, checked: names printable and at
/// most kMaxValueName bytes, values finite, tolerances in [0, 1).
std::vector<AgreedValue> decode_values(const std::byte*& at, std::uint32_t count, std::size_t bytes,
                                       const Link& link, std::uint64_t step) {
  std::vector<AgreedValue> values;
  const std::byte* const end = at + bytes;
  for (std::uint32_t k = 0; k < count; ++k) {
    if (end - at < 20) throw_malformed(link, step, "agreed_values", "shorter than its count");
    const auto name_bytes = get<std::uint32_t>(at);
    if (name_bytes == 0 || name_bytes > kMaxValueName ||
        end - at < 16 + std::ptrdiff_t(name_bytes)) {
      throw_malformed(link, step, fmt::format("agreed_values[{}]", k),
                      fmt::format("name of {} bytes: expected 1..{} within the record", name_bytes,
                                  kMaxValueName));
    }
    AgreedValue v;
    v.name.assign(reinterpret_cast<const char*>(at), name_bytes);
    at += name_bytes;
    check_printable(v.name, "agreed_values", link, step);
    v.value = get<double>(at);
    v.tolerance = get<double>(at);
    if (!std::isfinite(v.value) || !(v.tolerance >= 0 && v.tolerance < 1)) {
      throw_malformed(link, step, v.name,
                      fmt::format("value {} tolerance {}: expected a finite value and a "
                                  "tolerance in [0, 1)",
                                  v.value, v.tolerance));
    }
    values.push_back(std::move(v));
  }
  if (at != end) throw_malformed(link, step, "agreed_values", "longer than its count");
  return values;
}

}  // namespace

zmq::message_t encode_handshake(FrameType type, const Handshake& r) {
  const std::size_t cells = r.cell_nodes.size();
  const std::size_t value_bytes = values_bytes(r.scene.agreed);
  const std::size_t bytes = kHandshakeFixedBytes + value_bytes + r.scene.scene_hash.size() +
                            r.side_name.size() + 8 * cells + r.shared_memory.size() +
                            4 * r.faces.size();
  zmq::message_t frame = make_frame(type, r.scene.start_step, bytes);
  std::byte* at = payload(frame);
  put(at, r.scene.start_step);
  for (std::uint32_t v :
       {r.scene.total_cells, r.peer_index, r.peer_count, r.first_cell,
        static_cast<std::uint32_t>(cells), static_cast<std::uint32_t>(r.scene.scene_hash.size()),
        static_cast<std::uint32_t>(r.side_name.size()),
        static_cast<std::uint32_t>(r.shared_memory.size()),
        static_cast<std::uint32_t>(r.faces.size() / 3),
        static_cast<std::uint32_t>(r.scene.agreed.size()),
        static_cast<std::uint32_t>(value_bytes)}) {
    put(at, v);
  }
  put(at, r.contact_halo);
  auto put_bytes = [&](const void* data, std::size_t n) {
    if (n > 0) {
      std::memcpy(at, data, n);
    }
    at += n;
  };
  for (const AgreedValue& v : r.scene.agreed) {
    put(at, static_cast<std::uint32_t>(v.name.size()));
    put_bytes(v.name.data(), v.name.size());
    put(at, v.value);
    put(at, v.tolerance);
  }
  put_bytes(r.scene.scene_hash.data(), r.scene.scene_hash.size());
  put_bytes(r.side_name.data(), r.side_name.size());
  put_bytes(r.cell_nodes.data(), 4 * cells);
  put_bytes(r.shared_memory.data(), r.shared_memory.size());
  if (r.cell_faces.empty()) {
    std::memset(at, 0, 4 * cells);
    at += 4 * cells;
  } else {
    put_bytes(r.cell_faces.data(), 4 * cells);
  }
  put_bytes(r.faces.data(), 4 * r.faces.size());
  return frame;
}

Handshake decode_handshake(const zmq::message_t& frame, const FrameHeader& header,
                           const Link& link) {
  if (header.payload_bytes < kHandshakeFixedBytes) {
    throw_malformed(link, header.step, "payload_bytes",
                    fmt::format("{} record needs at least {} bytes, got {}", to_string(header.type),
                                kHandshakeFixedBytes, header.payload_bytes));
  }
  const std::byte* at = payload(frame);
  Handshake r;
  r.scene.start_step = get<std::uint64_t>(at);
  r.scene.total_cells = get<std::uint32_t>(at);
  r.peer_index = get<std::uint32_t>(at);
  r.peer_count = get<std::uint32_t>(at);
  r.first_cell = get<std::uint32_t>(at);
  const auto cells = get<std::uint32_t>(at);
  const auto hash_bytes = get<std::uint32_t>(at);
  const auto name_bytes = get<std::uint32_t>(at);
  const auto shm_bytes = get<std::uint32_t>(at);
  const auto face_count = get<std::uint32_t>(at);
  const auto value_count = get<std::uint32_t>(at);
  const auto value_bytes = get<std::uint32_t>(at);
  r.contact_halo = get<double>(at);
  if (!(r.contact_halo >= 0) || !std::isfinite(r.contact_halo)) {
    throw_malformed(link, header.step, "contact_halo",
                    fmt::format("{}: expected a finite width >= 0", r.contact_halo));
  }
  if (value_count > kMaxAgreedValues || value_bytes > kMaxAgreedValues * (20 + kMaxValueName)) {
    throw_malformed(link, header.step, "agreed_values",
                    fmt::format("{} values in {} bytes: at most {} values of names up to {} bytes",
                                value_count, value_bytes, kMaxAgreedValues, kMaxValueName));
  }
  for (const auto& [field, bytes] :
       {std::pair{"scene_hash", hash_bytes}, std::pair{"side_name", name_bytes},
        std::pair{"shared_memory", shm_bytes}}) {
    if (bytes > kMaxNameBytes) {
      throw_malformed(link, header.step, field, fmt::format("longer than {} bytes", kMaxNameBytes));
    }
  }
  const std::size_t expected = kHandshakeFixedBytes + value_bytes + hash_bytes + name_bytes +
                               8ull * cells + shm_bytes + 12ull * face_count;
  if (header.payload_bytes != expected) {
    throw_malformed(
        link, header.step, "payload_bytes",
        fmt::format("{} record with {} cells and {} faces needs {} bytes, got {}",
                    to_string(header.type), cells, face_count, expected, header.payload_bytes));
  }
  r.scene.agreed = decode_values(at, value_count, value_bytes, link, header.step);
  r.scene.scene_hash.assign(reinterpret_cast<const char*>(at), hash_bytes);
  at += hash_bytes;
  r.side_name.assign(reinterpret_cast<const char*>(at), name_bytes);
  at += name_bytes;
  check_printable(r.side_name, "side_name", link, header.step);
  r.cell_nodes.resize(cells);
  std::memcpy(r.cell_nodes.data(), at, 4ull * cells);
  at += 4ull * cells;
  for (std::size_t c = 0; c < cells; ++c) {
    if (r.cell_nodes[c] > kMaxCellNodes) {
      throw_malformed(link, header.step, fmt::format("cell_nodes[{}]", c),
                      fmt::format("{} nodes; at most {} per cell", r.cell_nodes[c], kMaxCellNodes));
    }
  }
  r.shared_memory.assign(reinterpret_cast<const char*>(at), shm_bytes);
  at += shm_bytes;
  r.cell_faces.resize(cells);
  std::memcpy(r.cell_faces.data(), at, 4ull * cells);
  at += 4ull * cells;
  r.faces.resize(3ull * face_count);
  std::memcpy(r.faces.data(), at, 12ull * face_count);
  // The surfaces must fit the cells they belong to: a stray index would send the fluid's
  // inside/outside test to another cell's (or no) node.
  std::size_t total = 0, next = 0;
  for (std::size_t c = 0; c < cells; ++c) {
    total += r.cell_faces[c];
  }
  if (total != face_count) {
    throw_malformed(link, header.step, "cell_faces",
                    fmt::format("the per-cell counts add up to {}, the record carries {} faces",
                                total, face_count));
  }
  for (std::size_t c = 0; c < cells; ++c) {
    for (std::size_t f = 0; f < 3ull * r.cell_faces[c]; ++f, ++next) {
      if (r.faces[next] >= r.cell_nodes[c]) {
        throw_malformed(link, header.step, fmt::format("faces[{}]", next / 3),
                        fmt::format("node {} of a cell with {} nodes (cell {})", r.faces[next],
                                    r.cell_nodes[c], c));
      }
    }
  }
  return r;
}

std::optional<std::string> scene_mismatch(const SceneIdentity& f, const SceneIdentity& m,
                                          std::string_view label) {
  if (f.scene_hash != m.scene_hash) {
    return mismatch("scene_hash", fmt::format("'{}'", f.scene_hash), label,
                    fmt::format("'{}'", m.scene_hash));
  }
  // Each side's values by name, in the fluid's order first: a value only one side hands over is
  // a mismatch too (the programs were built to agree on different things).
  for (const AgreedValue& a : f.agreed) {
    const AgreedValue* b = m.find(a.name);
    if (b == nullptr) return mismatch(a.name, a.value, label, "none");
    if (!same(a.value, b->value, std::max(a.tolerance, b->tolerance))) {
      return mismatch(a.name, a.value, label, b->value);
    }
  }
  for (const AgreedValue& b : m.agreed) {
    if (f.find(b.name) == nullptr) return mismatch(b.name, "none", label, b.value);
  }
  if (f.start_step != m.start_step) {
    return mismatch("start_step", f.start_step, label, m.start_step);
  }
  if (f.total_cells != m.total_cells) {
    return mismatch("total_cells", f.total_cells, label, m.total_cells);
  }
  return std::nullopt;
}

std::string membrane_label(std::string_view side_name) {
  return fmt::format("membrane '{}'", side_name);
}

}  // namespace dld::coupler
