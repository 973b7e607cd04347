// SPDX-License-Identifier: MIT
// Step counts on the command line (shared/cli_checks.hpp): whole numbers in a stated range, each
// refusal one short line naming the option and the value.
#include <gtest/gtest.h>

#include <vector>

#include "shared/cli_checks.hpp"

namespace {

/// The error of parsing `--steps value` (empty: accepted), and the steps parsed.
std::string parse(const std::string& value, std::int64_t* parsed = nullptr, bool zero = false) {
  CLI::App app{"t"};
  std::int64_t steps = -1;
  app.add_option("--steps", steps, "steps")->check(dld::step_count(zero));
  std::vector<std::string> args{"--steps", value};
  std::reverse(args.begin(), args.end());  // CLI11 takes them last first
  try {
    app.parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  if (parsed) *parsed = steps;
  return "";
}

TEST(StepCount, WholeNumbersInRangeAreTaken) {
  std::int64_t steps = 0;
  EXPECT_EQ(parse("2000", &steps), "");
  EXPECT_EQ(steps, 2000);
  EXPECT_EQ(parse("1000000000000000", &steps), "");
  EXPECT_EQ(parse("0", &steps, true), "");
  EXPECT_EQ(steps, 0);
}

TEST(StepCount, OthersAreRefusedInOneShortLine) {
  for (const std::string bad :
       {"abc", "0", "-5", "1.5", "2000x", "1000000000000001", "99999999999999999999"}) {
    const std::string e = parse(bad);
    EXPECT_NE(
        e.find("expected a whole number of steps from 1 to 1000000000000000, got '" + bad + "'"),
        std::string::npos)
        << bad << ": " << e;
    EXPECT_LT(e.size(), 160u) << e;
  }
}

}  // namespace
