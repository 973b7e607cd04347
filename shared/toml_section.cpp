// SPDX-License-Identifier: MIT
#include "shared/toml_section.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <sstream>

namespace dld {
namespace {

std::string location(const std::string& file, const toml::source_region& src) {
  if (src.begin.line == 0) return file;
  return fmt::format("{}:{}:{}", file, src.begin.line, src.begin.column);
}

std::string type_name(const toml::node& n) {
  std::ostringstream s;
  s << n.type();
  return s.str();
}

}  // namespace

std::shared_ptr<TomlDocument> TomlDocument::load(const std::string& path) {
  // toml++ reads a directory as an empty document ("missing table [scene]"): say what it is.
  if (std::filesystem::is_directory(path))
    throw InputError(fmt::format("{}: is a directory; expected a scene file (TOML)", path));
  try {
    auto doc = std::make_shared<TomlDocument>();
    doc->file_ = path;
    doc->root_ = toml::parse_file(path);
    return doc;
  } catch (const toml::parse_error& e) {
    std::string what(e.description());
    if (e.source().begin.line == 0)
      throw InputError(fmt::format("{}: cannot read scene: {}", path, what));
    throw InputError(fmt::format("{}: {}", location(path, e.source()), what));
  }
}

std::shared_ptr<TomlDocument> TomlDocument::parse(std::string_view text, const std::string& name) {
  try {
    auto doc = std::make_shared<TomlDocument>();
    doc->file_ = name;
    doc->root_ = toml::parse(text, name);
    return doc;
  } catch (const toml::parse_error& e) {
    throw InputError(
        fmt::format("{}: {}", location(name, e.source()), std::string(e.description())));
  }
}

void TomlDocument::reject_unknown(const std::vector<std::string>& owned_elsewhere) const {
  // Depth-first walk; a table is "known" if any key inside it was read, and each leaf must be read.
  std::string first_unknown;
  toml::source_region region;
  auto walk = [&](auto&& self, const toml::table& t, const std::string& prefix) -> void {
    for (auto&& [k, v] : t) {
      if (!first_unknown.empty()) return;
      std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
      if (prefix.empty()) {
        bool skip = false;
        for (const auto& o : owned_elsewhere) skip = skip || (o == key);
        if (skip) continue;
      }
      if (v.is_table() && !was_read(key)) {
        self(self, *v.as_table(), key);
      } else if (v.is_array_of_tables() && !was_read(key)) {
        const auto& arr = *v.as_array();
        for (std::size_t i = 0; i < arr.size(); ++i)
          self(self, *arr[i].as_table(), fmt::format("{}[{}]", key, i));
      } else if (!was_read(key)) {
        first_unknown = key;
        region = v.source();
      }
    }
  };
  walk(walk, root_, "");
  if (!first_unknown.empty())
    throw InputError(fmt::format("{}: key '{}': unknown key (misspelt, or not used by this scene)",
                                 location(file_, region), first_unknown));
}

TomlSection::TomlSection(std::shared_ptr<TomlDocument> doc, const toml::table* table,
                         std::string path)
    : doc_(std::move(doc)), table_(table), path_(std::move(path)) {}

TomlSection TomlSection::root(std::shared_ptr<TomlDocument> doc) {
  const toml::table* t = &doc->root();
  return TomlSection(std::move(doc), t, "");
}

std::string TomlSection::full(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

const toml::node* TomlSection::node(std::string_view key) const {
  doc_->mark_queried(full(key));
  return table_->get(key);
}

bool TomlSection::has(std::string_view key) const {
  return node(key) != nullptr;
}

std::string TomlSection::where(std::string_view key) const {
  const toml::node* n = node(key);
  return location(doc_->file(), n ? n->source() : table_->source());
}

void TomlSection::fail(std::string_view key, const std::string& what) const {
  throw InputError(fmt::format("{}: key '{}': {}", where(key), full(key), what));
}

const toml::node& TomlSection::required(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) fail(key, "missing (required)");
  doc_->mark_read(full(key));
  return *n;
}

double TomlSection::number(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_number()) fail(key, fmt::format("expected a number, got {}", type_name(n)));
  double v = n.value<double>().value();
  if (!std::isfinite(v)) fail(key, "expected a finite number");
  return v;
}

double TomlSection::number(std::string_view key, double fallback) const {
  return has(key) ? number(key) : fallback;
}

std::optional<double> TomlSection::optional_number(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return number(key);
}

double TomlSection::positive(std::string_view key) const {
  double v = number(key);
  if (!(v > 0)) fail(key, fmt::format("expected a positive number, got {}", v));
  return v;
}

double TomlSection::positive(std::string_view key, double fallback) const {
  return has(key) ? positive(key) : fallback;
}

double TomlSection::in_range(std::string_view key, double lo, double hi) const {
  double v = number(key);
  if (v < lo || v > hi) fail(key, fmt::format("expected a value in [{}, {}], got {}", lo, hi, v));
  return v;
}

double TomlSection::in_range(std::string_view key, double lo, double hi, double fallback) const {
  return has(key) ? in_range(key, lo, hi) : fallback;
}

std::int64_t TomlSection::integer(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_integer()) fail(key, fmt::format("expected an integer, got {}", type_name(n)));
  return n.value<std::int64_t>().value();
}

std::int64_t TomlSection::integer(std::string_view key, std::int64_t fallback) const {
  return has(key) ? integer(key) : fallback;
}

std::string TomlSection::string(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_string()) fail(key, fmt::format("expected a string, got {}", type_name(n)));
  return n.value<std::string>().value();
}

std::string TomlSection::string(std::string_view key, const std::string& fallback) const {
  return has(key) ? string(key) : fallback;
}

std::string TomlSection::choice(std::string_view key,
                                const std::vector<std::string>& choices) const {
  std::string v = string(key);
  for (const auto& c : choices)
    if (c == v) return v;
  fail(key, fmt::format("expected one of \"{}\", got \"{}\"", fmt::join(choices, "\", \""), v));
}

std::string TomlSection::choice(std::string_view key, const std::vector<std::string>& choices,
                                const std::string& fallback) const {
  return has(key) ? choice(key, choices) : fallback;
}

bool TomlSection::boolean(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_boolean()) fail(key, fmt::format("expected true or false, got {}", type_name(n)));
  return n.value<bool>().value();
}

bool TomlSection::boolean(std::string_view key, bool fallback) const {
  return has(key) ? boolean(key) : fallback;
}

std::vector<double> TomlSection::numbers(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_array()) fail(key, fmt::format("expected an array of numbers, got {}", type_name(n)));
  std::vector<double> out;
  for (const auto& e : *n.as_array()) {
    if (!e.is_number()) fail(key, "expected an array of numbers");
    out.push_back(e.value<double>().value());
  }
  return out;
}

TomlSection TomlSection::section(std::string_view key) const {
  const toml::node* n = node(key);
  if (n == nullptr) fail(key, "missing table (required)");
  if (!n->is_table()) fail(key, fmt::format("expected a table, got {}", type_name(*n)));
  return TomlSection(doc_, n->as_table(), full(key));
}

std::optional<TomlSection> TomlSection::optional_section(std::string_view key) const {
  if (!has(key)) return std::nullopt;
  return section(key);
}

const toml::table& TomlSection::raw_table(std::string_view key) const {
  const toml::node& n = required(key);
  if (!n.is_table()) fail(key, fmt::format("expected a table, got {}", type_name(n)));
  return *n.as_table();
}

std::vector<TomlSection> TomlSection::sections(std::string_view key) const {
  std::vector<TomlSection> out;
  const toml::node* n = node(key);
  if (n == nullptr) return out;
  if (!n->is_array_of_tables()) fail(key, fmt::format("expected [[{}]] tables", full(key)));
  const auto& arr = *n->as_array();
  for (std::size_t i = 0; i < arr.size(); ++i)
    out.emplace_back(doc_, arr[i].as_table(), fmt::format("{}[{}]", full(key), i));
  return out;
}

}  // namespace dld
