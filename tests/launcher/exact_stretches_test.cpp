// SPDX-License-Identifier: MIT
// <run>-exact-coupling.csv (dld-run --exact-coupling-for): stretches read back as written, the
// older two-column rows as finished ones, an unfinished stretch pending only where the run
// resumes at its end, and a malformed row refused with the file and line.
#include "coupler/launcher/exact_stretches.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "shared/input_error.hpp"

namespace {

namespace fs = std::filesystem;
using dld::coupler::ExactStretch;

struct Record {
  Record()
      : path((fs::temp_directory_path() / ("dld-exact-" + std::to_string(getpid()) + ".csv"))
                 .string()) {}
  ~Record() { fs::remove(path); }
  Record(const Record&) = delete;
  Record& operator=(const Record&) = delete;
  std::string path;
};

TEST(ExactStretches, ReadBackAsWrittenAndPendingOnlyWhereTheRunResumes) {
  const Record r;
  EXPECT_TRUE(dld::coupler::read_exact_stretches(r.path).empty()) << "no file: no stretch";
  dld::coupler::append_exact_stretch(r.path, {4700000, 4760000, 4760000});
  dld::coupler::append_exact_stretch(r.path, {5000000, 5020000, 5060000});
  const auto s = dld::coupler::read_exact_stretches(r.path);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[1].first, 5000000);
  EXPECT_EQ(s[1].last, 5020000);
  EXPECT_EQ(s[1].planned, 5060000);
  EXPECT_EQ(dld::coupler::pending_exact_end(s, 5020000), 5060000);
  EXPECT_EQ(dld::coupler::pending_exact_end(s, 5040000), 0) << "resumed elsewhere";
  EXPECT_EQ(dld::coupler::pending_exact_end({s[0]}, 4760000), 0) << "finished";
}

TEST(ExactStretches, TwoColumnRowsAreFinishedAndABadRowIsNamed) {
  const Record r;
  std::ofstream(r.path) << "first_step,last_step\n4700000,4760000\n";
  const auto s = dld::coupler::read_exact_stretches(r.path);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].planned, 4760000);
  std::ofstream(r.path, std::ios::app) << "4800000;4860000\n";
  try {
    dld::coupler::read_exact_stretches(r.path);
    FAIL() << "a malformed row was read";
  } catch (const dld::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(r.path + ":3: expected first_step,last_step"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
