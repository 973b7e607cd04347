// SPDX-License-Identifier: MIT
// Strict reading of TOML tables: required keys, typed values, range checks, and unknown keys
// reported with file, line and full key name.
#pragma once
#include <toml++/toml.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "shared/input_error.hpp"

namespace dld {

/// A parsed TOML file plus the set of keys that readers have consumed.
class TomlDocument {
 public:
  /// Parses `path`; a syntax error becomes an InputError "file:line:col: ...".
  static std::shared_ptr<TomlDocument> load(const std::string& path);
  /// Parses text held in memory; `name` stands for the file in messages.
  static std::shared_ptr<TomlDocument> parse(std::string_view text, const std::string& name);

  const std::string& file() const { return file_; }
  const toml::table& root() const { return root_; }
  void mark_read(const std::string& full_key) { read_.insert(full_key); }
  bool was_read(const std::string& full_key) const { return read_.count(full_key) != 0; }
  /// Every key a reader asked for, present in the file or not: the reader's vocabulary, which
  /// the tests compare with docs/scene-keys.md.
  void mark_queried(const std::string& full_key) { queried_.insert(full_key); }
  const std::set<std::string>& queried() const { return queried_; }

  /// Throws an InputError naming the first key that no reader consumed. Top-level tables in
  /// `owned_elsewhere` are skipped (another program reads and checks them).
  void reject_unknown(const std::vector<std::string>& owned_elsewhere = {}) const;

 private:
  std::string file_;
  toml::table root_;
  std::set<std::string> read_;
  std::set<std::string> queried_;
};

/// One table of a TomlDocument. Each getter marks the key as read.
class TomlSection {
 public:
  TomlSection(std::shared_ptr<TomlDocument> doc, const toml::table* table, std::string path);

  /// The root table of a document.
  static TomlSection root(std::shared_ptr<TomlDocument> doc);

  bool has(std::string_view key) const;
  const std::string& path() const { return path_; }
  const std::string& file() const { return doc_->file(); }

  double number(std::string_view key) const;
  double number(std::string_view key, double fallback) const;
  std::optional<double> optional_number(std::string_view key) const;
  double positive(std::string_view key) const;                   ///< required, > 0
  double positive(std::string_view key, double fallback) const;  ///< optional, > 0
  /// Required number with lo <= value <= hi.
  double in_range(std::string_view key, double lo, double hi) const;
  double in_range(std::string_view key, double lo, double hi, double fallback) const;
  std::int64_t integer(std::string_view key) const;
  std::int64_t integer(std::string_view key, std::int64_t fallback) const;
  std::string string(std::string_view key) const;
  std::string string(std::string_view key, const std::string& fallback) const;
  /// A string that must be one of `choices`.
  std::string choice(std::string_view key, const std::vector<std::string>& choices) const;
  std::string choice(std::string_view key, const std::vector<std::string>& choices,
                     const std::string& fallback) const;
  bool boolean(std::string_view key) const;
  bool boolean(std::string_view key, bool fallback) const;
  std::vector<double> numbers(std::string_view key) const;

  TomlSection section(std::string_view key) const;
  std::optional<TomlSection> optional_section(std::string_view key) const;
  /// Array of tables ([[key]] in TOML); empty when absent.
  std::vector<TomlSection> sections(std::string_view key) const;
  /// A required sub-table that the caller walks itself (its keys are free-form, e.g. dotted scene
  /// paths); the whole table counts as read.
  const toml::table& raw_table(std::string_view key) const;

  /// "file:line:col: key 'a.b': <what>" as an InputError. Uses the key's own line when present,
  /// else the table's line.
  [[noreturn]] void fail(std::string_view key, const std::string& what) const;

 private:
  const toml::node* node(std::string_view key) const;
  const toml::node& required(std::string_view key) const;
  std::string full(std::string_view key) const;
  std::string where(std::string_view key) const;

  std::shared_ptr<TomlDocument> doc_;
  const toml::table* table_;
  std::string path_;
};

}  // namespace dld
