// SPDX-License-Identifier: MIT
// The dilute-limit map (configs/study/dilute_modes.toml) and the expected-mode strings.
#include "analysis/expected_mode.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "shared/input_error.hpp"
#include "synthetic.hpp"

namespace dld::analysis {
namespace {

const std::string kMap = std::string(DLD_SOURCE_DIR) + "/configs/study/dilute_modes.toml";

using testing::error_of;

TEST(ExpectedMode, TheStudyMapHasAllNineCases) {
  const auto map = read_dilute_modes(kMap);
  EXPECT_EQ(map.size(), 9u);
  for (double d : {2.0, 4.4, 6.0}) {
    for (double ca : {0.2, 0.5, 1.0}) {
      const ExpectedMode e = lookup_expected_mode(map, kMap, d, ca);
      EXPECT_NE(e.source.find(kMap), std::string::npos) << e.source;
      // Every case has a mode: d = 6, Ca 1, "mixed" (unknown) in the dx = 0.8 um map, where its
      // run became unstable, is zigzag at dx = 0.4 um (2026-12-06).
      EXPECT_TRUE(e.known()) << d << " " << ca;
      if (d == 6.0 && ca == 1.0) EXPECT_EQ(e.mode, TransportMode::kZigzag);
    }
  }
}

TEST(ExpectedMode, LookupFindsTheEntryOrSaysUnknown) {
  const std::vector<DiluteModeEntry> map{{4.4, 0.5, TransportMode::kZigzag, "run a"},
                                         {6.0, 0.5, TransportMode::kDisplacement, "run b"}};
  EXPECT_EQ(lookup_expected_mode(map, "m.toml", 4.4, 0.5).mode, TransportMode::kZigzag);
  EXPECT_EQ(lookup_expected_mode(map, "m.toml", 6.0, 0.5).mode, TransportMode::kDisplacement);
  const ExpectedMode missing = lookup_expected_mode(map, "m.toml", 2.0, 0.5);
  EXPECT_FALSE(missing.known());
  EXPECT_NE(missing.source.find("no entry for d = 2"), std::string::npos) << missing.source;
  EXPECT_FALSE(lookup_expected_mode(map, "m.toml", 4.4, std::nullopt).known());
}

TEST(ExpectedMode, ModeStringsAndBadMapsAreOneLineErrors) {
  EXPECT_EQ(parse_expected_mode("zigzag", "--expected-mode"), TransportMode::kZigzag);
  EXPECT_NE(error_of([] {
              parse_expected_mode("sideways", "--expected-mode");
            }).find("--expected-mode: 'sideways' is not a mode"),
            std::string::npos);
  const std::string dir = testing::temp_dir("modes");
  std::ofstream(dir + "/key.toml") << "[[mode]]\nrow_shift_um = 2.0\ncapillary_number = 0.2\n"
                                      "mode = \"zigzag\"\nshift = 3\n";
  std::string e = error_of([&] { read_dilute_modes(dir + "/key.toml"); });
  EXPECT_NE(e.find(dir + "/key.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("mode[0].shift"), std::string::npos) << e;
  std::ofstream(dir + "/value.toml") << "[[mode]]\nrow_shift_um = 2.0\ncapillary_number = 0.2\n"
                                        "mode = \"sideways\"\n";
  e = error_of([&] { read_dilute_modes(dir + "/value.toml"); });
  EXPECT_NE(e.find("mode[0].mode"), std::string::npos) << e;
  std::ofstream(dir + "/missing.toml") << "[[mode]]\nrow_shift_um = 2.0\nmode = \"zigzag\"\n";
  e = error_of([&] { read_dilute_modes(dir + "/missing.toml"); });
  EXPECT_NE(e.find("capillary_number"), std::string::npos) << e;
  EXPECT_NE(error_of([&] { read_dilute_modes(dir + "/none.toml"); }).find("no such file"),
            std::string::npos);
}

}  // namespace
}  // namespace dld::analysis
