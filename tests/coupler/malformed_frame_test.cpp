// SPDX-License-Identifier: MIT
// Malformed frames (truncated, wrong magic, wrong count, out-of-order step, wrong type) are
// refused with a message naming the side, the step and the field, and the sender is told.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "coupler/shared_segment.hpp"
#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

struct BadFrame {
  const char* name;
  std::function<zmq::message_t()> make;
  std::string expected;  ///< the fluid's whole message
};

const std::vector<double> kTwoNodes(6, 1.5);
const std::string kPrefix = "fluid: malformed frame from membrane 'raw' at step 0: ";

zmq::message_t with_byte(zmq::message_t frame, std::size_t offset, std::uint8_t value) {
  static_cast<std::uint8_t*>(frame.data())[offset] = value;
  return frame;
}

zmq::message_t cut(const zmq::message_t& frame, std::size_t bytes) {
  return zmq::message_t(frame.data(), bytes);
}

class MalformedToFluid : public ::testing::TestWithParam<BadFrame> {};

TEST_P(MalformedToFluid, IsRefusedWithANamedError) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
                  context);
  RawPeer raw(context, fluid.endpoints()[0], false);
  raw.send(encode_handshake(FrameType::hello, hello_for(test_scene(1), {2})));
  fluid.initialize();
  ASSERT_TRUE(raw.receive());  // welcome
  raw.send(GetParam().make());
  try {
    (void)fluid.receive();
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()), GetParam().expected);
  }
  EXPECT_EQ(fluid.state(), State::failed);
  auto told = raw.receive();  // the sender learns why the run stopped
  ASSERT_TRUE(told);
  EXPECT_EQ(RawPeer::type_of(*told), FrameType::error);
  EXPECT_EQ(read_error_text(*told, read_header(*told, {"t", "p"}, 0)), GetParam().expected);
}

INSTANTIATE_TEST_SUITE_P(
    Frames, MalformedToFluid,
    ::testing::Values(
        BadFrame{"TruncatedHeader", [] { return zmq::message_t(10); },
                 kPrefix + "field 'header': frame of 10 bytes is shorter than the 24-byte header"},
        BadFrame{"TruncatedPayload", [] { return cut(encode_step(0, kTwoNodes, kTwoNodes), 120); },
                 kPrefix + "field 'payload_bytes': header announces 104 bytes but the step frame "
                           "carries 96"},
        BadFrame{"WrongMagic",
                 [] { return with_byte(encode_step(0, kTwoNodes, kTwoNodes), 0, 'X'); },
                 kPrefix + "field 'magic': expected 0x43444c44 (\"DLDC\"), got 0x43444c58"},
        BadFrame{"WrongVersion",
                 [] { return with_byte(encode_step(0, kTwoNodes, kTwoNodes), 4, 2); },
                 kPrefix + "field 'version': expected 4, got 2"},
        BadFrame{"UnknownType",
                 [] { return with_byte(encode_step(0, kTwoNodes, kTwoNodes), 6, 99); },
                 kPrefix + "field 'type': unknown frame type 99"},
        BadFrame{"WrongType", [] { return encode_velocities(0, kTwoNodes); },
                 kPrefix + "field 'type': expected step, shutdown or error, got velocities"},
        BadFrame{"WrongCount",
                 [] {
                   const std::vector<double> three(9, 1.0);
                   return encode_step(0, three, three);
                 },
                 kPrefix + "field 'node_count': expected 2 nodes, got 3"},
        BadFrame{"CountDisagreesWithLength",
                 [] {
                   zmq::message_t f = make_frame(FrameType::step, 0, step_payload_bytes(3));
                   const std::uint64_t two = 2;
                   std::memcpy(payload(f), &two, 8);
                   return f;
                 },
                 kPrefix + "field 'payload_bytes': 2 nodes need 104 bytes in a step frame, got "
                           "152"},
        BadFrame{"NoHeldSteps", [] { return encode_held_steps(0, 0, kTwoNodes, kTwoNodes); },
                 kPrefix + "field 'held_steps': expected 1 to 1000000 steps, got 0"},
        BadFrame{"HeldStepsWithoutForces",
                 [] { return cut(encode_held_steps(0, 5, kTwoNodes, kTwoNodes), 24 + 16 + 48); },
                 kPrefix + "field 'payload_bytes': header announces 112 bytes but the held_steps "
                           "frame carries 64"},
        BadFrame{"OutOfOrderStep", [] { return encode_step(5, kTwoNodes, kTwoNodes); },
                 kPrefix + "field 'step': expected 0, got 5"},
        BadFrame{"NaNForce",
                 [] {
                   std::vector<double> f(kTwoNodes);
                   f[4] = std::nan("");
                   return encode_step(0, kTwoNodes, f);
                 },
                 kPrefix + "field 'forces': node 1 has a non-finite value (nan)"},
        BadFrame{"InfinitePosition",
                 [] {
                   std::vector<double> x(kTwoNodes);
                   x[0] = -HUGE_VAL;
                   return encode_step(0, x, kTwoNodes);
                 },
                 kPrefix + "field 'positions': node 0 has a non-finite value (-inf)"}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(MalformedHandshake, ShortHelloIsRefused) {
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
                  context);
  RawPeer raw(context, fluid.endpoints()[0], false);
  zmq::message_t hello = make_frame(FrameType::hello, 0, 10);
  raw.send(std::move(hello));
  try {
    fluid.initialize();
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              "fluid: malformed frame from membrane peer 0 at step 0: field 'payload_bytes': "
              "hello record needs at least 60 bytes, got 10");
  }
}

// Hellos whose fields would make the fluid allocate without bound or print control characters.
TEST(MalformedHandshake, HugeCellsAndUnprintableNamesAreRefusedNamingTheField) {
  const std::vector<std::pair<Handshake, std::string>> cases{
      {hello_for(test_scene(1), {2147483648u}),
       "field 'cell_nodes[0]': 2147483648 nodes; at most 1000000 per cell"},
      {hello_for(test_scene(1), {2}, "bad\nname"),
       "field 'side_name': byte 3 is 0x0a: expected printable ASCII"},
      {hello_for(test_scene(1), {2}, std::string("nul\0x", 5)),
       "field 'side_name': byte 3 is 0x00: expected printable ASCII"},
      {hello_for(test_scene(1), {2}, "caf\xc3\xa9"),
       "field 'side_name': byte 3 is 0xc3: expected printable ASCII"}};
  for (const auto& [hello, expected] : cases) {
    zmq::context_t context;
    TempDir dir;
    FluidSide fluid({test_scene(1), fluid_endpoints(Kind::inproc, 1, dir), {}, test_options()},
                    context);
    RawPeer raw(context, fluid.endpoints()[0], false);
    raw.send(encode_handshake(FrameType::hello, hello));
    try {
      fluid.initialize();
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const CouplerError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

// On a shared-memory link the data frames are the small ones; a full step frame is refused.
TEST(MalformedSharedLink, FullStepFrameIsRefused) {
  TempDir dir;
  zmq::context_t context;
  FluidSide fluid({test_scene(1), {"ipc://" + (dir.path() / "c").string()}, {}, test_options()},
                  context);
  RawPeer raw(context, fluid.endpoints()[0], false);
  SharedSegment segment = SharedSegment::create(segment_bytes(2), "test");
  Handshake hello = hello_for(test_scene(1), {2});
  hello.shared_memory = segment.name();
  raw.send(encode_handshake(FrameType::hello, hello));
  fluid.initialize();
  EXPECT_TRUE(fluid.shared_memory(0));
  ASSERT_TRUE(raw.receive());  // welcome
  raw.send(encode_step(0, kTwoNodes, kTwoNodes));
  try {
    (void)fluid.receive();
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()),
              kPrefix + "field 'type': expected step_shared, shutdown or error, got step");
  }
}

struct BadReply {
  const char* name;
  std::function<zmq::message_t()> make;
  std::string expected;
};

class MalformedToMembrane : public ::testing::TestWithParam<BadReply> {};

TEST_P(MalformedToMembrane, IsRefusedWithANamedError) {
  zmq::context_t context;
  RawPeer raw_fluid(context, std::string("inproc://malformed-") + GetParam().name, true);
  MembraneSide m({test_scene(1), raw_fluid.endpoint(), "membrane-0", 0, 1, 0, {2}, test_options()},
                 context);
  std::thread fluid_thread([&] {
    ASSERT_TRUE(raw_fluid.receive());  // hello
    raw_fluid.send(encode_handshake(FrameType::welcome, hello_for(test_scene(1), {2}, "fluid")));
    ASSERT_TRUE(raw_fluid.receive());  // step 0
    raw_fluid.send(GetParam().make());
    auto told = raw_fluid.receive();
    ASSERT_TRUE(told);
    EXPECT_EQ(RawPeer::type_of(*told), FrameType::error);
  });
  m.initialize();
  std::vector<double> u(6);
  try {
    (void)m.advance(kTwoNodes, kTwoNodes, u);
    FAIL() << "accepted";
  } catch (const CouplerError& e) {
    EXPECT_EQ(std::string(e.what()), GetParam().expected);
  }
  fluid_thread.join();
}

const std::string kToMembrane = "membrane 'membrane-0': malformed frame from fluid at step 0: ";

INSTANTIATE_TEST_SUITE_P(
    Frames, MalformedToMembrane,
    ::testing::Values(
        BadReply{"WrongCount", [] { return encode_velocities(0, std::vector<double>(3, 1.0)); },
                 kToMembrane + "field 'node_count': expected 2 nodes, got 1"},
        BadReply{"OutOfOrderStep", [] { return encode_velocities(1, kTwoNodes); },
                 kToMembrane + "field 'step': expected 0, got 1"},
        BadReply{"Truncated", [] { return cut(encode_velocities(0, kTwoNodes), 30); },
                 kToMembrane + "field 'payload_bytes': header announces 56 bytes but the "
                               "velocities frame carries 6"},
        BadReply{"WrongType", [] { return encode_step(0, kTwoNodes, kTwoNodes); },
                 kToMembrane + "field 'type': expected velocities, shutdown or error, got step"},
        BadReply{"NaNVelocity",
                 [] {
                   std::vector<double> u(kTwoNodes);
                   u[5] = std::nan("");
                   return encode_velocities(0, u);
                 },
                 kToMembrane + "field 'velocities': node 1 has a non-finite value (nan)"}),
    [](const auto& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace dld::coupler::test
