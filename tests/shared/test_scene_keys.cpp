// SPDX-License-Identifier: MIT
// docs/scene-keys.md is the reference of scene keys: it must list exactly the keys the parser
// reads, and every example value in it must be accepted.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

#include "shared/scene.hpp"

namespace {

struct Row {
  std::string key, example;
};

std::vector<Row> documented_rows() {
  std::ifstream in(std::string(DLD_SOURCE_DIR) + "/docs/scene-keys.md");
  EXPECT_TRUE(in.good()) << "docs/scene-keys.md missing";
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("| ", 0) != 0 || line.find('.') == std::string::npos) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line.substr(1));
    std::string cell;
    while (std::getline(ss, cell, '|')) {
      const auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
      cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
    }
    if (cells.size() >= 5 && cells[0] != "key") rows.push_back({cells[0], cells[4]});
  }
  return rows;
}

TEST(SceneKeys, DocumentedKeysAreExactlyTheParsersKeys) {
  const auto rows = documented_rows();
  ASSERT_GT(rows.size(), 10u);
  // A scene made of every documented example value.
  std::map<std::string, std::string> tables;
  std::set<std::string> documented;
  for (const auto& r : rows) {
    documented.insert(r.key);
    if (r.example == "-") continue;
    const auto dot = r.key.find('.');
    tables[r.key.substr(0, dot)] += r.key.substr(dot + 1) + " = " + r.example + "\n";
  }
  std::string text;
  for (const auto& [t, body] : tables) text += "[" + t + "]\n" + body;
  const dld::Scene s = dld::parse_scene(text, "scene-keys.md");
  std::set<std::string> queried;
  for (const auto& k : s.document->queried())
    if (k.find('.') != std::string::npos) queried.insert(k);
  for (const auto& k : queried)
    EXPECT_TRUE(documented.count(k)) << "parser reads undocumented key " << k;
  for (const auto& k : documented)
    EXPECT_TRUE(queried.count(k)) << "documented key never read: " << k;
  for (const auto& r : rows)
    if (r.example != "-") {
      EXPECT_TRUE(s.document->was_read(r.key)) << r.key;
    }
}

}  // namespace
