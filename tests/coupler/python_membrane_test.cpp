// SPDX-License-Identifier: MIT
// docs/protocol.md is enough to write a membrane in another language: python_membrane.py, written
// from the document alone, runs against the C++ fluid side over ipc. Skipped without python3-zmq.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "coupler_test_util.hpp"

namespace dld::coupler::test {
namespace {

TEST(PythonMembrane, SpeaksTheDocumentedProtocol) {
  if (std::system("/usr/bin/python3 -c 'import zmq' > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "python3-zmq (Debian) not installed";
  }
  TempDir dir;
  const SceneIdentity s = test_scene(2);
  FluidSide fluid({s, {"ipc://" + (dir.path() / "fluid").string()}, {}, test_options(10'000ms)});
  const auto log = dir.path() / "python.log";
  const std::string command = fmt::format(
      "/usr/bin/python3 {}/tests/coupler/python_membrane.py {} 3 4,5 {} {:.17g} {:.17g} {:.17g} "
      "{:.17g} {:.17g} {:.17g} {:.17g} > {} 2>&1",
      DLD_SOURCE_DIR, fluid.endpoints()[0], s.scene_hash, s.find("dx_m")->value,
      s.find("dt_s")->value, s.find("density_kg_m3")->value, s.find("lambda_m")->value,
      s.find("radius_m")->value, s.find("depth_m")->value, s.find("shift_m")->value, log.string());
  int status = -1;
  std::thread python([&] { status = std::system(command.c_str()); });
  int steps = 0;
  try {
    fluid.initialize();
    ASSERT_EQ(fluid.node_count(), 9u);
    while (fluid.receive()) {
      const auto x = fluid.positions();
      const auto f = fluid.forces();
      std::vector<double> u(x.size());
      for (std::size_t i = 0; i < x.size(); ++i) {
        ASSERT_EQ(x[i], 0.5 * static_cast<double>(i) + static_cast<double>(fluid.step()));
        ASSERT_EQ(f[i], -0.25 * static_cast<double>(i));
        u[i] = 2 * x[i];
      }
      fluid.send_velocities(u);
      ++steps;
    }
    fluid.finalize();
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  python.join();
  std::stringstream output;
  output << std::ifstream(log).rdbuf();
  EXPECT_EQ(status, 0) << output.str();
  EXPECT_EQ(steps, 3);
  EXPECT_EQ(fluid.state(), State::finalized);
}

}  // namespace
}  // namespace dld::coupler::test
