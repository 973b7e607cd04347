// SPDX-License-Identifier: MIT
#include "analysis/expected_mode.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>

#include "shared/input_error.hpp"
#include "shared/toml_section.hpp"

namespace dld::analysis {

TransportMode parse_expected_mode(const std::string& text, const std::string& what) {
  if (text == "zigzag") {
    return TransportMode::kZigzag;
  }
  if (text == "displacement") {
    return TransportMode::kDisplacement;
  }
  throw InputError(
      fmt::format("{}: '{}' is not a mode: expected zigzag or displacement", what, text));
}

std::vector<DiluteModeEntry> read_dilute_modes(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(fmt::format("{}: no such file (expected a dilute-limit mode map)", path));
  }
  const auto doc = TomlDocument::load(path);
  std::vector<DiluteModeEntry> out;
  for (const TomlSection& s : TomlSection::root(doc).sections("mode")) {
    DiluteModeEntry e;
    e.row_shift_um = s.positive("row_shift_um");
    e.capillary_number = s.positive("capillary_number");
    const std::string m = s.choice("mode", {"zigzag", "displacement", "mixed", "undecided"});
    e.mode = m == "zigzag"         ? TransportMode::kZigzag
             : m == "displacement" ? TransportMode::kDisplacement
             : m == "mixed"        ? TransportMode::kMixed
                                   : TransportMode::kUndecided;
    e.source = s.string("source", "");
    out.push_back(e);
  }
  doc->reject_unknown();
  return out;
}

ExpectedMode lookup_expected_mode(const std::vector<DiluteModeEntry>& map, const std::string& file,
                                  double d_um, std::optional<double> capillary_number) {
  if (!capillary_number) {
    return {TransportMode::kUndecided,
            "the run file has no capillary_number to look up in " + file};
  }
  const auto same = [](double a, double b) { return std::abs(a - b) <= 1e-6 * std::abs(b); };
  for (const auto& e : map) {
    if (!same(d_um, e.row_shift_um) || !same(*capillary_number, e.capillary_number)) {
      continue;
    }
    const std::string where =
        fmt::format("{}: d = {} um, Ca = {}{}", file, e.row_shift_um, e.capillary_number,
                    e.source.empty() ? "" : " (" + e.source + ")");
    return {e.mode, e.mode == TransportMode::kZigzag || e.mode == TransportMode::kDisplacement
                        ? where
                        : fmt::format("{} in {}", to_string(e.mode), where)};
  }
  return {TransportMode::kUndecided,
          fmt::format("no entry for d = {} um, Ca = {} in {}", d_um, *capillary_number, file)};
}

}  // namespace dld::analysis
