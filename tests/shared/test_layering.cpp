// SPDX-License-Identifier: MIT
// The include rules of docs/architecture.md, for every source file by folder: shared/ includes
// none of the others; fluid/ and membrane/ never include each other; coupler/ knows no physics
// (neither fluid/ nor membrane/); analysis/ reads run files and includes shared/ only; tracers/
// is a membrane-side program of the coupler and knows no fluid or membrane code. The programs'
// coupled modes (listed by name below, not by a name pattern) are where a side meets the coupler;
// every other file of fluid/ and membrane/ is library code and may not include coupler/.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <string>

namespace {

namespace fs = std::filesystem;

const std::set<std::string> kAll{"shared", "fluid", "membrane", "coupler", "analysis", "tracers"};

/// Folders a file of `folder` may include (besides its own), by its path below the source root.
std::set<std::string> allowed(const std::string& folder, const std::string& relative) {
  static const std::set<std::string> programs{
      "fluid/coupled_main.cpp",    "fluid/coupled_main.hpp",    "fluid/main.cpp",
      "membrane/coupled_main.cpp", "membrane/coupled_main.hpp", "membrane/main.cpp"};
  if (folder == "shared" || folder == "analysis") return {"shared"};
  if (folder == "fluid" || folder == "membrane") {
    if (programs.count(relative)) return {"shared", "coupler"};
    return {"shared"};
  }
  if (folder == "coupler") return {"shared"};  // the launcher starts programs, it links none
  if (folder == "tracers") return {"shared", "coupler"};
  return {};
}

TEST(Layering, EverySourceFileIncludesOnlyWhatItsFolderMay) {
  const std::regex include(R"re(#include\s+"([a-z_]+)/)re");
  std::map<std::string, int> files;
  for (const std::string& folder : kAll) {
    const fs::path root = fs::path(DLD_SOURCE_DIR) / folder;
    ASSERT_TRUE(fs::exists(root)) << root;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
      const auto ext = e.path().extension();
      if (ext != ".cpp" && ext != ".hpp" && ext != ".h") continue;
      const std::string relative = fs::relative(e.path(), DLD_SOURCE_DIR).string();
      const std::set<std::string> may = allowed(folder, relative);
      ++files[folder];
      std::ifstream in(e.path());
      std::string line;
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, include)) continue;
        const std::string to = m[1].str();
        if (to == folder || !kAll.count(to)) continue;  // itself, or a library (<...>-like path)
        EXPECT_TRUE(may.count(to)) << relative << " includes " << to << "/";
      }
    }
  }
  for (const std::string& folder : kAll)
    EXPECT_GT(files[folder], 0) << folder << "/ has no sources";
  EXPECT_GT(files["fluid"] + files["membrane"], 20);
}

// The rules bite: a library file of fluid/ that included coupler/ would be reported.
TEST(Layering, RulesRefuseWhatDocsForbid) {
  EXPECT_FALSE(allowed("fluid", "fluid/domain.cpp").count("coupler"));
  EXPECT_TRUE(allowed("fluid", "fluid/coupled_main.cpp").count("coupler"));
  EXPECT_FALSE(allowed("membrane", "membrane/main.cpp").count("fluid"));
  EXPECT_FALSE(allowed("tracers", "tracers/main.cpp").count("membrane"));
  EXPECT_FALSE(allowed("coupler", "coupler/launcher/launcher_main.cpp").count("analysis"));
  EXPECT_FALSE(allowed("shared", "shared/guarded_main.hpp").count("coupler"));
}

}  // namespace
