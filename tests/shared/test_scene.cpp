// SPDX-License-Identifier: MIT
// Scene reading: a good scene resolves; each kind of bad scene stops with one line naming the
// file, the line and the key.
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "shared/scene.hpp"
#include "tests/common/base_scene.hpp"

namespace {

const char* const kGood = dld::testing::kBaseScene;

std::string replace(std::string text, const std::string& from, const std::string& to) {
  auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return text.replace(pos, from.size(), to);
}

// Returns the error message of parsing `text`, or "" if it parsed.
std::string error_of(const std::string& text) {
  try {
    dld::parse_scene(text, "bad.toml");
  } catch (const dld::InputError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& text, const std::string& key, int line,
                  const std::string& what) {
  const std::string msg = error_of(text);
  ASSERT_FALSE(msg.empty()) << "scene was accepted";
  EXPECT_NE(msg.find("bad.toml:" + std::to_string(line) + ":"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'" + key + "'"), std::string::npos) << msg;
  EXPECT_NE(msg.find(what), std::string::npos) << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "message must be one line: " << msg;
}

TEST(Scene, GoodSceneResolvesLatticeValues) {
  const dld::Scene s = dld::parse_scene(kGood, "good.toml");
  EXPECT_EQ(s.nx(), 80);
  EXPECT_EQ(s.ny(), 80);
  EXPECT_EQ(s.nz(), 12);
  EXPECT_NEAR(s.cell_lu().shift, 11.0, 1e-12);
  EXPECT_NEAR(s.cell_lu().radius, 25.0, 1e-12);
  EXPECT_EQ(s.lattice.collision, dld::CollisionKind::kTrt);
  EXPECT_GT(s.force_x_lu(), 0.0);
  EXPECT_EQ(s.output.file, "runs/t.h5");
  // Re = 0.1 through the plane-Poiseuille estimate: U = p' H^2 / (12 mu) = Re nu / G.
  const double nu = s.fluid.viscosity_Pa_s / s.fluid.density_kg_m3;
  const double u =
      s.drive.pressure_gradient_Pa_per_m * 4.8e-6 * 4.8e-6 / (12 * s.fluid.viscosity_Pa_s);
  EXPECT_NEAR(u * 12e-6 / nu, 0.1, 1e-12);
  EXPECT_NE(s.describe().find("80 x 80 x 12 nodes"), std::string::npos);
}

TEST(Scene, UnknownKeyIsNamed) {
  expect_error(replace(kGood, "dx_um = 0.4", "dx_um = 0.4\ndx_nm = 400"), "lattice.dx_nm", 11,
               "unknown key");
}

TEST(Scene, UnknownTableIsNamed) {
  expect_error(std::string(kGood) + "[fluids]\nviscosity_Pa_s = 1e-3\n", "fluids.viscosity_Pa_s",
               14, "unknown key");
}

TEST(Scene, MissingRequiredKeyIsNamed) {
  expect_error(replace(kGood, "depth_um = 4.8\n", ""), "geometry.depth_um", 4, "missing");
}

TEST(Scene, WrongTypeIsNamed) {
  expect_error(replace(kGood, "depth_um = 4.8", "depth_um = \"4.8 um\""), "geometry.depth_um", 7,
               "expected a number");
}

TEST(Scene, TauAtOrBelowOneHalfIsRefused) {
  expect_error(replace(kGood, "dx_um = 0.4", "dx_um = 0.4\ntau = 0.5"), "lattice.tau", 11, "> 1/2");
}

TEST(Scene, PillarWiderThanBoxIsRefused) {
  expect_error(replace(kGood, "pillar_radius_um = 10.0", "pillar_radius_um = 16.0"),
               "geometry.pillar_radius_um", 5, "smaller than the pillar spacing");
}

TEST(Scene, NegativeSizeIsRefused) {
  expect_error(replace(kGood, "depth_um = 4.8", "depth_um = -4.8"), "geometry.depth_um", 7,
               "positive");
}

TEST(Scene, NegativeShiftIsRefused) {
  expect_error(replace(kGood, "row_shift_um = 4.4", "row_shift_um = -1.0"), "geometry.row_shift_um",
               8, "0 <= d < lambda");
}

TEST(Scene, LatticeSpacingMustFitTheBox) {
  expect_error(replace(kGood, "dx_um = 0.4", "dx_um = 0.6"), "lattice.dx_um", 10, "whole number");
}

TEST(Scene, DriveNeedsExactlyOneOfReynoldsAndPressureGradient) {
  expect_error(replace(kGood, "reynolds = 0.1", "reynolds = 0.1\npressure_gradient_Pa_per_m = 1e6"),
               "drive.reynolds", 12, "exactly one");
  expect_error(replace(kGood, "reynolds = 0.1", ""), "drive.pressure_gradient_Pa_per_m", 11,
               "exactly one");
}

TEST(Scene, TooFastFlowIsRefused) {
  expect_error(replace(kGood, "reynolds = 0.1", "reynolds = 10.0"), "drive.reynolds", 12, "Mach");
}

TEST(Scene, UnknownCollisionIsRefused) {
  expect_error(replace(kGood, "dx_um = 0.4", "dx_um = 0.4\ncollision = \"lbgk\""),
               "lattice.collision", 11, "expected one of");
}

TEST(Scene, EveryRegisteredCollisionIsAccepted) {
  for (std::size_t k = 0; k < dld::kCollisionNames.size(); ++k) {
    const std::string name(dld::kCollisionNames[k]);
    const dld::Scene s = dld::parse_scene(
        replace(kGood, "dx_um = 0.4", "dx_um = 0.4\ncollision = \"" + name + "\""), "c.toml");
    EXPECT_EQ(static_cast<std::size_t>(s.lattice.collision), k) << name;
    std::string upper = name;
    for (char& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    EXPECT_NE(s.describe().find("(" + upper), std::string::npos) << s.describe();
  }
}

TEST(Scene, SyntaxErrorGivesLine) {
  const std::string msg = error_of(replace(kGood, "depth_um = 4.8", "depth_um = = 4.8"));
  EXPECT_NE(msg.find("bad.toml:7:"), std::string::npos) << msg;
}

TEST(Scene, MissingFileIsNamed) {
  try {
    dld::load_scene("/nonexistent/scene.toml");
    FAIL() << "no error";
  } catch (const dld::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.toml"), std::string::npos) << e.what();
  }
}

TEST(Scene, ADirectoryIsNotASceneFile) {
  try {
    dld::load_scene("/tmp");
    FAIL() << "no error";
  } catch (const dld::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/tmp: is a directory; expected a scene file (TOML)");
  }
}

TEST(Scene, MeshOutputIsOffUnlessAsked) {
  EXPECT_EQ(dld::parse_scene(kGood, "good.toml").output.mesh_every, 0);
  const std::string on = std::string(kGood) + "[output]\nmesh_every = 250\n";
  EXPECT_EQ(dld::parse_scene(on, "good.toml").output.mesh_every, 250);
}

TEST(Scene, BadMeshEveryIsNamed) {
  expect_error(std::string(kGood) + "[output]\nmesh_every = -5\n", "output.mesh_every", 14, ">= 0");
  expect_error(std::string(kGood) + "[output]\nmesh_every = 2.5\n", "output.mesh_every", 14,
               "expected an integer");
  expect_error(std::string(kGood) + "[output]\nmesh_every = \"often\"\n", "output.mesh_every", 14,
               "expected an integer");
}

TEST(Scene, TimeScaleSeparationIsOffUnlessAsked) {
  const dld::Scene exact = dld::parse_scene(kGood, "good.toml");
  EXPECT_EQ(exact.coupling.force_every, 1);
  EXPECT_EQ(exact.coupling.viscosity_field_every, 1);
  const dld::Scene held = dld::parse_scene(
      std::string(kGood) + "[coupling]\nforce_every = 5\nviscosity_field_every = 2\n", "good.toml");
  EXPECT_EQ(held.coupling.force_every, 5);
  EXPECT_EQ(held.coupling.viscosity_field_every, 2);
  EXPECT_NE(held.describe().find("membrane forces every 5 step(s), viscosity field every 2"),
            std::string::npos)
      << held.describe();
  EXPECT_FALSE(held.coupling.spread_held);
  const dld::Scene spread = dld::parse_scene(
      std::string(kGood) + "[coupling]\nforce_every = 5\nspread_held = true\n", "good.toml");
  EXPECT_TRUE(spread.coupling.spread_held);
  EXPECT_NE(spread.describe().find("every 5 step(s) (spread held with them)"), std::string::npos)
      << spread.describe();
  EXPECT_FALSE(spread.coupling.interpolation_held);
  const dld::Scene weights = dld::parse_scene(std::string(kGood) +
                                                  "[coupling]\nforce_every = 5\nspread_held = "
                                                  "true\ninterpolation_held = true\n",
                                              "good.toml");
  EXPECT_TRUE(weights.coupling.interpolation_held);
  EXPECT_NE(weights.describe().find("(spread and its weights held with them)"), std::string::npos);
}

// dld-run --exact-coupling-for: the programs couple exactly (nothing held) but, interrupted, still
// stop where the held coupling they hand back to resumes exactly (here lcm(5, 2) = 10).
TEST(Scene, MadeExactACouplingHoldsNothingButStopsWhereTheHeldOneResumes) {
  dld::Scene s = dld::parse_scene(std::string(kGood) +
                                      "[coupling]\nforce_every = 5\nviscosity_field_every = "
                                      "2\nspread_held = true\ninterpolation_held = true\n",
                                  "good.toml");
  EXPECT_TRUE(s.coupling.holds());
  s.coupling.make_exact();
  EXPECT_FALSE(s.coupling.holds());
  EXPECT_EQ(s.coupling.force_every, 1);
  EXPECT_EQ(s.coupling.viscosity_field_every, 1);
  EXPECT_FALSE(s.coupling.spread_held);
  EXPECT_FALSE(s.coupling.interpolation_held);
  EXPECT_EQ(s.coupling.exact_resume_every(), 10);
}

TEST(Scene, BadUpdateIntervalsAreNamed) {
  expect_error(std::string(kGood) + "[coupling]\nforce_every = 0\n", "coupling.force_every", 14,
               "expected 1 to 1000 steps between membrane force updates");
  expect_error(std::string(kGood) + "[coupling]\nviscosity_field_every = 5000\n",
               "coupling.viscosity_field_every", 14, "expected 1 to 1000 steps");
  expect_error(std::string(kGood) + "[coupling]\nforce_every = 1.5\n", "coupling.force_every", 14,
               "expected an integer");
  expect_error(std::string(kGood) + "[coupling]\nspread_held = 1\n", "coupling.spread_held", 14,
               "expected true or false");
  expect_error(std::string(kGood) + "[coupling]\nforce_every = 5\ninterpolation_held = true\n",
               "coupling.interpolation_held", 15, "needs spread_held = true");
  // The volume correction happens where the membrane programs are awake: at force updates.
  expect_error(std::string(kGood) + "[coupling]\nforce_every = 5\nvolume_correction_every = 12\n",
               "coupling.volume_correction_every", 15,
               "expected 0 (never) or a multiple of force_every (5) up to 1000000 steps");
  expect_error(std::string(kGood) + "[coupling]\nvolume_correction_every = -100\n",
               "coupling.volume_correction_every", 14, "expected 0 (never) or a multiple");
  const dld::Scene corrected = dld::parse_scene(
      std::string(kGood) + "[coupling]\nforce_every = 5\nvolume_correction_every = 100\n",
      "good.toml");
  EXPECT_EQ(corrected.coupling.volume_correction_every, 100);
  EXPECT_NE(corrected.describe().find("cell volumes restored every 100 steps"), std::string::npos);
  EXPECT_EQ(dld::parse_scene(kGood, "good.toml").coupling.volume_correction_every, 0);
}

TEST(Scene, TablesOfOtherProgramsAreLeftToThem) {
  // [membrane] is read by the membrane program; the fluid reader must not reject it.
  EXPECT_NO_THROW(
      dld::parse_scene(std::string(kGood) + "[membrane]\nmodel = \"skalak\"\n", "m.toml"));
}

}  // namespace
