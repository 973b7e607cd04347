// SPDX-License-Identifier: MIT
#include "synthetic.hpp"

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
