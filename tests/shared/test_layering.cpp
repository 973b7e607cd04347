// SPDX-License-Identifier: MIT
// The include rules of docs/architecture.md: shared/ includes none of the others; fluid/ and
// membrane/ never include each other; coupler/ knows no physics (neither fluid/ nor membrane/);
// analysis/ reads run files and includes shared/ only.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;

TEST(Layering, FoldersIncludeOnlyWhatTheyMay) {
  const std::map<std::string, std::set<std::string>> forbidden{
      {"shared", {"fluid", "membrane", "coupler", "analysis"}},
      {"fluid", {"membrane", "coupler"}},
      {"membrane", {"fluid", "coupler"}},
      {"coupler", {"fluid", "membrane"}},
      {"analysis", {"fluid", "membrane", "coupler"}},
  };
  const std::regex include(R"re(#include\s+"([a-z_]+)/)re");
  int files = 0;
  for (const auto& [folder, banned] : forbidden) {
    const fs::path root = fs::path(DLD_SOURCE_DIR) / folder;
    if (!fs::exists(root)) continue;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      const auto ext = e.path().extension();
      if (ext != ".cpp" && ext != ".hpp") continue;
      // Program files (main.cpp, *_main.cpp/hpp) are where a side meets the coupler; libraries
      // must not.
      if (e.path().filename().string().find("main.") != std::string::npos) continue;
      ++files;
      std::ifstream in(e.path());
      std::string line;
      while (std::getline(in, line)) {
        std::smatch m;
        if (std::regex_search(line, m, include)) {
          EXPECT_FALSE(banned.count(m[1].str())) << e.path() << " includes " << m[1] << "/";
        }
      }
    }
  }
  EXPECT_GT(files, 10);
}

}  // namespace
