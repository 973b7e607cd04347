// SPDX-License-Identifier: MIT
// The frame codec and endpoint strings on their own, without sockets.
#include "coupler/frame.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/frame_pool.hpp"
#include "coupler/handshake.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {
namespace {

const Link kLink{"fluid", "membrane 'm-0'"};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const CouplerError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Frame, HeaderLayoutIsLittleEndianAsDocumented) {
  const zmq::message_t frame = encode_shutdown(0x0102030405060708ull);
  ASSERT_EQ(frame.size(), kHeaderBytes);
  const auto* b = static_cast<const unsigned char*>(frame.data());
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(b), 4), "DLDC");
  EXPECT_EQ(b[4], 4);  // version, low byte first
  EXPECT_EQ(b[5], 0);
  EXPECT_EQ(b[6], 5);  // type shutdown
  EXPECT_EQ(b[8], 0x08);
  EXPECT_EQ(b[15], 0x01);
  for (int i = 16; i < 24; ++i) EXPECT_EQ(b[i], 0) << i;  // empty payload
}

TEST(Frame, StepRoundTripIsBitExact) {
  const std::vector<double> x{-0.0, 4.9e-324, 1.0 / 3.0, 1e308, -7.5, 2.0};
  const std::vector<double> f{1.0, 2.0, 3.0, 4.0, 5.0, -6.25};
  const zmq::message_t frame = encode_step(42, x, f);
  EXPECT_EQ(frame.size(), kHeaderBytes + step_payload_bytes(2));
  const FrameHeader h = read_header(frame, kLink, 42);
  EXPECT_EQ(h.type, FrameType::step);
  EXPECT_EQ(h.step, 42u);
  const std::byte* data = read_nodes(frame, h, 2, 2, kLink);
  EXPECT_EQ(std::memcmp(data, x.data(), 48), 0);
  EXPECT_EQ(std::memcmp(data + 48, f.data(), 48), 0);
}

TEST(Frame, TruncatedHeaderIsNamed) {
  zmq::message_t frame(10);
  EXPECT_EQ(error_of([&] { read_header(frame, kLink, 3); }),
            "fluid: malformed frame from membrane 'm-0' at step 3: field 'header': frame of 10 "
            "bytes is shorter than the 24-byte header");
}

TEST(Frame, WrongMagicVersionTypeAndLengthAreNamed) {
  auto corrupt = [](std::size_t offset, std::uint8_t value) {
    zmq::message_t frame = encode_velocities(1, std::vector<double>(3, 1.0));
    static_cast<std::uint8_t*>(frame.data())[offset] = value;
    return frame;
  };
  EXPECT_NE(error_of([&] { read_header(corrupt(0, 'X'), kLink, 1); }).find("field 'magic'"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              read_header(corrupt(4, 9), kLink, 1);
            }).find("field 'version': expected 4, got 9"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              read_header(corrupt(6, 77), kLink, 1);
            }).find("field 'type': unknown frame type 77"),
            std::string::npos);
  EXPECT_NE(
      error_of([&] { read_header(corrupt(16, 200), kLink, 1); }).find("field 'payload_bytes'"),
      std::string::npos);
}

TEST(Frame, NodeCountMismatchIsNamed) {
  const zmq::message_t frame = encode_velocities(7, std::vector<double>(6, 0.5));
  const FrameHeader h = read_header(frame, kLink, 7);
  EXPECT_EQ(error_of([&] { read_nodes(frame, h, 3, 1, kLink); }),
            "fluid: malformed frame from membrane 'm-0' at step 7: field 'node_count': expected "
            "3 nodes, got 2");
}

TEST(Frame, ErrorTextStaysOneLine) {
  const zmq::message_t frame = encode_error(2, "first line\nsecond line");
  EXPECT_EQ(read_error_text(frame, read_header(frame, kLink, 2)), "first line second line");
}

TEST(Handshake, RecordRoundTrips) {
  Handshake h;
  h.scene.scene_hash = "abc";
  h.scene.agreed = {{"dt_s", 2.1e-8, 1e-12}, {"a name of a value", -3.5, 0.25}};
  h.scene.start_step = 99;
  h.scene.total_cells = 17;
  h.side_name = "membrane-3";
  h.peer_index = 3;
  h.peer_count = 4;
  h.first_cell = 12;
  h.cell_nodes = {1002, 642, 1002};
  const zmq::message_t frame = encode_handshake(FrameType::hello, h);
  const FrameHeader header = read_header(frame, kLink, 99);
  const Handshake back = decode_handshake(frame, header, kLink);
  EXPECT_EQ(back.scene.scene_hash, "abc");
  ASSERT_EQ(back.scene.agreed.size(), 2u);
  EXPECT_EQ(back.scene.agreed[0].name, "dt_s");
  EXPECT_EQ(back.scene.agreed[0].value, 2.1e-8);
  EXPECT_EQ(back.scene.agreed[1].name, "a name of a value");
  EXPECT_EQ(back.scene.agreed[1].value, -3.5);
  EXPECT_EQ(back.scene.agreed[1].tolerance, 0.25);
  EXPECT_EQ(back.scene.start_step, 99u);
  EXPECT_EQ(back.side_name, "membrane-3");
  EXPECT_EQ(back.first_cell, 12u);
  EXPECT_EQ(back.cell_nodes, h.cell_nodes);
  EXPECT_EQ(back.cell_faces, std::vector<std::uint32_t>(3, 0));  // no surfaces given: none sent
  EXPECT_TRUE(back.faces.empty());
}

// The cell surfaces (protocol v2) travel with the hello, cell after cell, with local node indices.
Handshake two_tetrahedra() {
  Handshake h;
  h.side_name = "membrane-0";
  h.cell_nodes = {4, 5};
  h.cell_faces = {4, 4};
  h.faces = {0, 1, 2, 0, 3, 1, 1, 3, 2, 2, 3, 0, 0, 1, 2, 0, 4, 1, 1, 4, 2, 2, 4, 0};
  return h;
}

TEST(Handshake, CellSurfacesRoundTrip) {
  const Handshake h = two_tetrahedra();
  const zmq::message_t frame = encode_handshake(FrameType::hello, h);
  const Handshake back = decode_handshake(frame, read_header(frame, kLink, 0), kLink);
  EXPECT_EQ(back.cell_faces, h.cell_faces);
  EXPECT_EQ(back.faces, h.faces);
}

TEST(Handshake, SurfaceIndexBeyondItsCellIsMalformed) {
  Handshake h = two_tetrahedra();
  h.faces[3] = 4;  // cell 0 has nodes 0..3 only
  const zmq::message_t frame = encode_handshake(FrameType::hello, h);
  try {
    decode_handshake(frame, read_header(frame, kLink, 0), kLink);
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_NE(
        std::string(e.what()).find("field 'faces[1]': node 4 of a cell with 4 nodes (cell 0)"),
        std::string::npos)
        << e.what();
  }
}

TEST(Handshake, SurfaceCountsThatDisagreeAreMalformed) {
  const Handshake h = two_tetrahedra();
  zmq::message_t frame = encode_handshake(FrameType::hello, h);
  // cell_faces[1] lies after the fixed bytes, the name (10), cell_nodes (8) and cell_faces[0]
  // (no named values, no scene hash, no shared memory here).
  const std::uint32_t three = 3;
  std::memcpy(
      static_cast<std::byte*>(frame.data()) + kHeaderBytes + kHandshakeFixedBytes + 10 + 8 + 4,
      &three, 4);
  try {
    decode_handshake(frame, read_header(frame, kLink, 0), kLink);
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_NE(
        std::string(e.what()).find(
            "field 'cell_faces': the per-cell counts add up to 7, the record carries 8 faces"),
        std::string::npos)
        << e.what();
  }
}

TEST(Handshake, MismatchMessageNamesFieldAndBothValues) {
  SceneIdentity fluid;
  fluid.agreed = {{"dt_s", 2.1e-8, 1e-12}};
  SceneIdentity membrane = fluid;
  membrane.agreed[0].value = 2.2e-8;
  EXPECT_EQ(scene_mismatch(fluid, membrane, "membrane 'membrane-0'").value(),
            "handshake: field 'dt_s': fluid has 2.1e-08, membrane 'membrane-0' has 2.2e-08");
  membrane.agreed[0].value = 2.1e-8 * (1 + 1e-14);  // another program's round-off is accepted
  EXPECT_FALSE(scene_mismatch(fluid, membrane, "m").has_value());
}

TEST(Endpoint, AcceptsTheThreeTransports) {
  EXPECT_EQ(parse_endpoint("inproc://coupler"), Transport::inproc);
  EXPECT_EQ(parse_endpoint("ipc:///tmp/run/coupler"), Transport::ipc);
  EXPECT_EQ(parse_endpoint("tcp://127.0.0.1:5555"), Transport::tcp);
}

TEST(Endpoint, RefusesOthersWithANamedError) {
  EXPECT_THROW(parse_endpoint("udp://127.0.0.1:5555"), InputError);
  EXPECT_THROW(parse_endpoint("tcp://127.0.0.1"), InputError);
  EXPECT_THROW(parse_endpoint("ipc://" + std::string(200, 'a')), InputError);
  try {
    parse_endpoint("pgm://x");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("coupler endpoint 'pgm://x'"), std::string::npos);
  }
}

TEST(Endpoint, PeerEndpointsOnePerPeer) {
  EXPECT_EQ(peer_endpoints("ipc:///tmp/c", 2),
            (std::vector<std::string>{"ipc:///tmp/c-0", "ipc:///tmp/c-1"}));
  EXPECT_EQ(peer_endpoints("tcp://127.0.0.1:6000", 2),
            (std::vector<std::string>{"tcp://127.0.0.1:6000", "tcp://127.0.0.1:6001"}));
  EXPECT_EQ(peer_endpoints("tcp://127.0.0.1:*", 2),
            (std::vector<std::string>{"tcp://127.0.0.1:*", "tcp://127.0.0.1:*"}));
}

}  // namespace
}  // namespace dld::coupler

namespace dld::coupler {
namespace {

TEST(FramePool, ReusesABufferOnceZeroMqReleasesIt) {
  FramePool pool;
  const void* first = nullptr;
  {
    zmq::message_t a = pool.make(FrameType::velocities, 1, 800);
    first = a.data();
    zmq::message_t b = pool.make(FrameType::velocities, 2, 800);  // a still held: a new buffer
    EXPECT_NE(b.data(), first);
    EXPECT_EQ(pool.blocks(), 2u);
  }
  zmq::message_t c = pool.make(FrameType::velocities, 3, 400);  // smaller fits a freed buffer
  EXPECT_EQ(pool.blocks(), 2u);
  const FrameHeader h = read_header(c, kLink, 3);
  EXPECT_EQ(h.type, FrameType::velocities);
  EXPECT_EQ(h.payload_bytes, 400u);
}

TEST(FramePool, FramesMayOutliveThePool) {
  zmq::message_t survivor;
  {
    FramePool pool;
    survivor = pool.make(FrameType::step, 0, 1 << 20);
    std::memset(payload(survivor), 7, 1 << 20);
  }  // the pool is gone; the buffer goes when the last frame does (checked under ASan)
  EXPECT_EQ(static_cast<unsigned char*>(survivor.data())[kHeaderBytes + 100], 7);
}

TEST(FramePool, NeverHoldsMoreThanAFewBuffers) {
  FramePool pool;
  std::vector<zmq::message_t> held;
  for (int i = 0; i < 10; ++i) held.push_back(pool.make(FrameType::step, 0, 100));
  EXPECT_LE(pool.blocks(), 4u);  // beyond that, plain frames: a leak cannot grow without bound
}

}  // namespace
}  // namespace dld::coupler

namespace dld::coupler::test {
namespace {

std::string decode_error(const SceneIdentity& scene) {
  Handshake h;
  h.scene = scene;
  h.side_name = "m";
  const zmq::message_t frame = encode_handshake(FrameType::hello, h);
  try {
    decode_handshake(frame, read_header(frame, kLink, 0), kLink);
  } catch (const CouplerError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(Handshake, BadAgreedValuesAreMalformed) {
  SceneIdentity s;
  s.agreed = {{"dt\ns", 1.0, 0.0}};
  EXPECT_NE(decode_error(s).find("field 'agreed_values': byte 2 is 0x0a: expected printable ASCII"),
            std::string::npos)
      << decode_error(s);
  s.agreed = {{"dt_s", std::nan(""), 0.0}};
  EXPECT_NE(decode_error(s).find("field 'dt_s': value nan tolerance 0: expected a finite value"),
            std::string::npos)
      << decode_error(s);
  s.agreed = {{"dt_s", 1.0, 2.0}};
  EXPECT_NE(decode_error(s).find("a tolerance in [0, 1)"), std::string::npos) << decode_error(s);
  s.agreed = {{std::string(65, 'a'), 1.0, 0.0}};
  EXPECT_NE(decode_error(s).find("name of 65 bytes: expected 1..64"), std::string::npos)
      << decode_error(s);
  s.agreed.assign(65, {"x", 1.0, 0.0});
  EXPECT_NE(decode_error(s).find("65 values in"), std::string::npos) << decode_error(s);
  s.agreed = {{"dt_s", 1.0, 1e-12}};
  EXPECT_EQ(decode_error(s), "accepted");
}

}  // namespace
}  // namespace dld::coupler::test
