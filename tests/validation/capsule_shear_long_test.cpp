// SPDX-License-Identifier: MIT
// Capsule in shear at full resolution (label long): the steady Taylor deformation of a
// neo-Hookean capsule against Ramanujan & Pozrikidis, J. Fluid Mech. 361 (1998) 117 (within 5 %),
// and a Skalak capsule at small Ca against the small-deformation formula. The set-up and the
// numbers are in docs/validation.md (Capsule in simple shear).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "capsule_shear.hpp"

namespace dld::validation {
namespace {

/// The full-resolution set-up of docs/validation.md.
CapsuleShearSetup full_resolution(double ca) {
  CapsuleShearSetup s;
  s.radius = 6.0;
  s.nx = s.ny = 48;
  s.nz = 60;
  s.faces = 1280;
  s.reynolds = 0.1;
  s.capillary = ca;
  s.strain = 6.0;
  s.sample_every = 100;
  return s;
}

/// Steady D of the reference: the end of the digitised curve (as in reference/README.md).
double reference_steady(const std::string& file) {
  std::ifstream in(std::string(DLD_TEST_DATA) + "/capsule_shear/" + file);
  EXPECT_TRUE(in) << file;
  std::string line;
  double last_t = -1, last_d = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double t, d;
    if (row >> t >> d && t > last_t) {
      last_t = t;
      last_d = d;
    }
  }
  return last_d;
}

class CapsuleShearLong : public ::testing::TestWithParam<double> {};

TEST_P(CapsuleShearLong, SteadyDeformationMatchesRamanujanPozrikidis) {
  const double ca = GetParam();
  const CapsuleShearRun r = run_capsule_shear(full_resolution(ca));
  const double d = mean_deformation(r, 0.7 * r.strain.back());
  const double ref = reference_steady(fmt::format("neo_hookean_pozrikidis1998_ca_{}.csv", ca));
  fmt::print("Ca {}: D {:.4f}, Ramanujan-Pozrikidis {:.4f}, error {:+.2f} %, {} steps, {:.0f} s\n",
             ca, d, ref, 100 * (d / ref - 1), r.steps, r.wall_seconds);
  EXPECT_NEAR(d, ref, 0.05 * ref);
}

INSTANTIATE_TEST_SUITE_P(Ramanujan1998, CapsuleShearLong, ::testing::Values(0.025, 0.05, 0.1, 0.2),
                         [](const auto& p) {
                           return "Ca" + std::to_string(static_cast<int>(p.param * 1000 + 0.5));
                         });

// Small-deformation theory (Barthes-Biesel & Rallison 1981, as in reference/README.md):
// D = (5/4) (2 + nu_s)/(1 + nu_s) mu gammadot a / G_s with nu_s = C/(1 + C) for Skalak.
TEST(CapsuleShearLong, SkalakSmallDeformationMatchesTheory) {
  CapsuleShearSetup s = full_resolution(0.005);  // mu gammadot a / G_s = 0.015
  s.law = MembraneLaw::skalak;
  s.skalak_c = 10.0;
  s.strain = 4.0;
  const CapsuleShearRun r = run_capsule_shear(s);
  const double d = mean_deformation(r, 0.7 * r.strain.back());
  const double nu_s = s.skalak_c / (1 + s.skalak_c);
  const double theory = 1.25 * (2 + nu_s) / (1 + nu_s) * 3 * s.capillary;
  fmt::print("Skalak C {}: D {:.5f}, small-deformation theory {:.5f}, error {:+.2f} %\n",
             s.skalak_c, d, theory, 100 * (d / theory - 1));
  EXPECT_NEAR(d, theory, 0.05 * theory);
}

}  // namespace
}  // namespace dld::validation
