// SPDX-License-Identifier: MIT
// The fluid run file's XDMF side file: one grid per snapshot step, also when the run ends on a
// snapshot step (it used to list that step twice, the second copy reading empty in ParaView;
// issue 18, item 11).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dld_scene.hpp"
#include "fluid/fluid_run.hpp"
#include "tests/temp_dir.hpp"

namespace dld::fluid {
namespace {

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(FluidOutput, ARunEndingOnASnapshotStepListsEachStepOnce) {
  Scene scene = testing::dld_scene(0.8, 4.4);
  scene.output.snapshot_every = 20;
  scene.run.steady_tolerance = 0;
  const test::TempDir dir("dld-fluid-output");
  FluidRunOptions opt;
  opt.max_steps = 40;
  opt.progress = false;
  opt.output = (dir.path() / "run.h5").string();
  run_fluid(scene, opt);
  std::ifstream in(dir.path() / "run.xmf");
  std::stringstream xmf;
  xmf << in.rdbuf();
  EXPECT_EQ(count(xmf.str(), "<Grid Name=\"step 20\""), 1) << xmf.str();
  EXPECT_EQ(count(xmf.str(), "<Grid Name=\"step 40\""), 1) << xmf.str();
  EXPECT_EQ(count(xmf.str(), "GridType=\"Uniform\""), 2) << xmf.str();
}

}  // namespace
}  // namespace dld::fluid
