// SPDX-License-Identifier: MIT
// docs/membrane-scene-keys.md against the parser: every key the membrane scene reader asks for is
// documented, and every documented key is read somewhere.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "membrane/model_registry.hpp"

namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Keys asked for through TomlSection getters, e.g. m.positive("radius_um") or
/// s->numbers("forces_pN"); also the string-array reader and the exactly-one-of lists.
std::set<std::string> parsed_keys() {
  std::set<std::string> keys;
  const std::regex getter(
      R"re((?:\.|->)(?:number|positive|in_range|integer|string|choice|boolean|numbers|has|section|optional_section|sections|fail)\(\s*"([A-Za-z_0-9]+)")re");
  const std::regex other(R"re((?:strings\(scene, m, |keys\{|, )"([A-Za-z_0-9]+)")re");
  // The scene reader and every model's from_scene() (the membrane/*.cpp files that define one: a
  // new model's file is read without a list here).
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(DLD_SOURCE_DIR) + "/membrane")) {
    if (entry.path().extension() != ".cpp") continue;
    const std::string text = slurp(entry.path().string());
    if (entry.path().filename() != "membrane_scene.cpp" &&
        text.find("::from_scene(") == std::string::npos)
      continue;  // not a scene reader
    for (const std::regex* re : {&getter, &other})
      for (auto it = std::sregex_iterator(text.begin(), text.end(), *re);
           it != std::sregex_iterator(); ++it)
        keys.insert((*it)[1]);
  }
  // Each model's table, [membrane.<name>], is read by name through the registry.
  for (const auto& m : dld::membrane::model_registry()) keys.insert(std::string(m.name));
  return keys;
}

/// Keys in the first column of the doc's tables, in "exactly one of `a` and `b`" sentences, and
/// the table names in headings ([membrane.x] -> x, [cells] -> cells).
std::set<std::string> documented_keys() {
  const std::string text = slurp(std::string(DLD_SOURCE_DIR) + "/docs/membrane-scene-keys.md");
  std::set<std::string> keys;
  const std::regex row(R"(\n\| `([A-Za-z_0-9]+)` \|)");
  const std::regex heading(R"(\n##+ \[\[?(?:membrane\.|cells\.)?([a-z_]+)\])");
  const std::regex sentence(R"(Exactly one of `([A-Za-z_0-9]+)` .*? and `([A-Za-z_0-9]+)`)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator();
       ++it)
    keys.insert((*it)[1]);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), heading);
       it != std::sregex_iterator(); ++it)
    keys.insert((*it)[1]);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), sentence);
       it != std::sregex_iterator(); ++it) {
    keys.insert((*it)[1]);
    keys.insert((*it)[2]);
  }
  return keys;
}

TEST(SceneKeyReference, EveryParsedKeyIsDocumented) {
  const auto doc = documented_keys();
  ASSERT_GT(doc.size(), 25u);  // the extraction itself works
  ASSERT_TRUE(doc.count("forces_pN") && doc.count("area_modulus_ref_lu") && doc.count("cell"));
  // Table names read as sections but documented as headings.
  for (const std::string& k : parsed_keys()) {
    if (k == "membrane") continue;
    EXPECT_TRUE(doc.count(k)) << "key '" << k << "' is read but not in docs/membrane-scene-keys.md";
  }
}

TEST(SceneKeyReference, EveryDocumentedKeyIsParsed) {
  const auto parsed = parsed_keys();
  ASSERT_GT(parsed.size(), 25u);
  ASSERT_TRUE(parsed.count("forces_pN") && parsed.count("area_modulus_ref_lu") &&
              parsed.count("cell"));
  // Model tables are looked up by the model's name, not by a literal.
  const std::set<std::string> by_name{"skalak", "neo_hookean", "bending", "volume", "area"};
  for (const std::string& k : documented_keys()) {
    if (by_name.count(k)) continue;
    EXPECT_TRUE(parsed.count(k)) << "documented key '" << k << "' is not read by the parser";
  }
}

}  // namespace
