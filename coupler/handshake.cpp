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

bool same(double a, double b) {
  return a == b || std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b));
}

}  // namespace

zmq::message_t encode_handshake(FrameType type, const Handshake& r) {
  const std::size_t cells = r.cell_nodes.size();
  const std::size_t bytes = kHandshakeFixedBytes + r.scene.scene_hash.size() + r.side_name.size() +
                            8 * cells + r.shared_memory.size() + 4 * r.faces.size();
  zmq::message_t frame = make_frame(type, r.scene.start_step, bytes);
  std::byte* at = payload(frame);
  for (double v : {r.scene.dx_m, r.scene.dt_s, r.scene.density_kg_m3, r.scene.lambda_m,
                   r.scene.radius_m, r.scene.depth_m, r.scene.shift_m}) {
    put(at, v);
  }
  put(at, r.scene.start_step);
  for (std::uint32_t v :
       {r.scene.total_cells, r.peer_index, r.peer_count, r.first_cell,
        static_cast<std::uint32_t>(cells), static_cast<std::uint32_t>(r.scene.scene_hash.size()),
        static_cast<std::uint32_t>(r.side_name.size()),
        static_cast<std::uint32_t>(r.shared_memory.size()),
        static_cast<std::uint32_t>(r.faces.size() / 3)}) {
    put(at, v);
  }
  auto put_bytes = [&](const void* data, std::size_t n) {
    if (n > 0) {
      std::memcpy(at, data, n);
    }
    at += n;
  };
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
  r.scene.dx_m = get<double>(at);
  r.scene.dt_s = get<double>(at);
  r.scene.density_kg_m3 = get<double>(at);
  r.scene.lambda_m = get<double>(at);
  r.scene.radius_m = get<double>(at);
  r.scene.depth_m = get<double>(at);
  r.scene.shift_m = get<double>(at);
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
  for (const auto& [field, bytes] :
       {std::pair{"scene_hash", hash_bytes}, std::pair{"side_name", name_bytes},
        std::pair{"shared_memory", shm_bytes}}) {
    if (bytes > kMaxNameBytes) {
      throw_malformed(link, header.step, field, fmt::format("longer than {} bytes", kMaxNameBytes));
    }
  }
  const std::size_t expected = kHandshakeFixedBytes + hash_bytes + name_bytes + 8ull * cells +
                               shm_bytes + 12ull * face_count;
  if (header.payload_bytes != expected) {
    throw_malformed(
        link, header.step, "payload_bytes",
        fmt::format("{} record with {} cells and {} faces needs {} bytes, got {}",
                    to_string(header.type), cells, face_count, expected, header.payload_bytes));
  }
  r.scene.scene_hash.assign(reinterpret_cast<const char*>(at), hash_bytes);
  at += hash_bytes;
  r.side_name.assign(reinterpret_cast<const char*>(at), name_bytes);
  at += name_bytes;
  // The name goes into every message about this side: printable ASCII only, or a newline or NUL
  // in it would cut or forge those lines.
  for (std::size_t i = 0; i < r.side_name.size(); ++i) {
    const auto c = static_cast<unsigned char>(r.side_name[i]);
    if (c < 0x20 || c > 0x7e) {
      throw_malformed(link, header.step, "side_name",
                      fmt::format("byte {} is 0x{:02x}: expected printable ASCII", i, c));
    }
  }
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
  const std::pair<const char*, std::pair<double, double>> doubles[] = {
      {"dx_m", {f.dx_m, m.dx_m}},
      {"dt_s", {f.dt_s, m.dt_s}},
      {"density_kg_m3", {f.density_kg_m3, m.density_kg_m3}},
      {"lambda_m", {f.lambda_m, m.lambda_m}},
      {"radius_m", {f.radius_m, m.radius_m}},
      {"depth_m", {f.depth_m, m.depth_m}},
      {"shift_m", {f.shift_m, m.shift_m}},
  };
  for (const auto& [field, values] : doubles) {
    if (!same(values.first, values.second)) {
      return mismatch(field, values.first, label, values.second);
    }
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
