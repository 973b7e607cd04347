// SPDX-License-Identifier: MIT
#include "synthetic.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

namespace dld::analysis::testing {

std::string temp_dir(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() /
                 ("dld-analysis-test-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

}  // namespace dld::analysis::testing

namespace {

/// Removes this test program's temporary directories when it ends.
class RemoveTempDirs : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ec;
    std::filesystem::remove_all(
        std::filesystem::temp_directory_path() / ("dld-analysis-test-" + std::to_string(getpid())),
        ec);
  }
};

[[maybe_unused]] ::testing::Environment* const kRemoveTempDirs =
    ::testing::AddGlobalTestEnvironment(new RemoveTempDirs);

}  // namespace
