// SPDX-License-Identifier: MIT
// Label "long": the separation distance at dx = 0.8, 0.4 and 0.32 um for the three row shifts and
// both pillar wall rules; the values reported in docs/validation.md. Checks that s converges:
// the change from 0.4 to 0.32 um is smaller than from 0.8 to 0.4 um.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "dld_scene.hpp"
#include "fluid/fluid_run.hpp"

namespace dld::fluid {
namespace {

void check_convergence(const std::string& wall_rule) {
  for (double d : {2.0, 4.4, 6.0}) {
    std::vector<double> s;
    for (double dx : {0.8, 0.4, 0.32}) {
      const Scene scene = testing::dld_scene(dx, d, "trt", 0.1, wall_rule);
      FluidRunOptions opt;
      opt.write_file = false;
      opt.progress = false;
      const FluidRunSummary r = run_fluid(scene, opt);
      EXPECT_TRUE(r.steady);
      std::printf(
          "%s: d = %.1f um, dx = %.2f um: s = %.4f um, Re = %.4f, steps %ld, mass change %.1e\n",
          wall_rule.c_str(), d, dx, r.separation_um, r.reynolds, static_cast<long>(r.steps),
          r.relative_mass_change);
      std::fflush(stdout);
      s.push_back(r.separation_um);
    }
    EXPECT_LT(std::abs(s[2] - s[1]), std::abs(s[1] - s[0])) << wall_rule << ", d = " << d;
  }
}

TEST(SeparationLong, ConvergesWithLatticeSpacingBounceBack) {
  check_convergence("bounce_back");
}
TEST(SeparationLong, ConvergesWithLatticeSpacingBouzidi) {
  check_convergence("bouzidi");
}

}  // namespace
}  // namespace dld::fluid
