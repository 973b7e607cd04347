// SPDX-License-Identifier: MIT
// Long runs (label "long"): many steps over every transport with two membrane peers stay
// bit-exact and end cleanly; buffers are reused, so memory does not grow with the step count.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

class LongRun : public ::testing::TestWithParam<Kind> {};

TEST_P(LongRun, FiftyThousandStepsStayExact) {
  constexpr int kSteps = 50'000;
  const std::vector<std::vector<std::uint32_t>> split{{40, 60}, {100}};
  zmq::context_t context;
  TempDir dir;
  FluidSide fluid({test_scene(3), fluid_endpoints(GetParam(), 2, dir), {}, test_options()},
                  context);
  std::string errors[2];
  std::vector<std::thread> membranes;
  for (std::uint32_t k = 0; k < 2; ++k) {
    membranes.emplace_back([&, k] {
      try {
        MembraneSide m({test_scene(3), fluid.endpoints()[k], fmt::format("membrane-{}", k), k, 2,
                        k == 0 ? 0u : 2u, split[k], test_options()},
                       context);
        m.initialize();
        const std::size_t first_node = k == 0 ? 0 : 100;
        std::vector<double> x(3 * m.node_count()), f(x.size()), expected;
        for (int s = 0; s < kSteps; ++s) {
          fill_nodes(m.step(), first_node, x, f);
          const auto u = m.exchange(x, f);
          ASSERT_TRUE(u.has_value());
          dummy_velocities(s, x, f, expected);
          ASSERT_TRUE(std::equal(u->begin(), u->end(), expected.begin())) << "step " << s;
        }
        m.finalize();
      } catch (const std::exception& e) {
        errors[k] = e.what();
      }
    });
  }
  fluid.initialize();
  std::vector<double> u;
  int steps = 0;
  while (fluid.receive()) {
    dummy_velocities(fluid.step(), fluid.positions(), fluid.forces(), u);
    fluid.send_velocities(u);
    ++steps;
  }
  fluid.finalize();
  for (auto& t : membranes) t.join();
  EXPECT_EQ(steps, kSteps);
  EXPECT_EQ(errors[0], "");
  EXPECT_EQ(errors[1], "");
}

INSTANTIATE_TEST_SUITE_P(Transports, LongRun, ::testing::Values(Kind::inproc, Kind::ipc, Kind::tcp),
                         [](const auto& p) { return name(p.param); });

}  // namespace
}  // namespace dld::coupler::test
