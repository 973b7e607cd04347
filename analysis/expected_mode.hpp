// SPDX-License-Identifier: MIT
// The expected mode of a run (SPEC section 7): what a single cell does in the same device, (d, Ca).
// It comes from the dilute-limit map (configs/study/dilute_modes.toml, the format that
// scripts/dilute-map writes: [[mode]] tables with row_shift_um, capillary_number, mode, source) or
// from the command line. "mixed" (or a missing entry) means unknown: no failure probability.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "shared/column_tracker.hpp"

namespace dld::analysis {

struct ExpectedMode {
  TransportMode mode = TransportMode::kUndecided;  ///< kZigzag or kDisplacement when known
  std::string source;                              ///< where it came from, for the terminal
  bool known() const {
    return mode == TransportMode::kZigzag || mode == TransportMode::kDisplacement;
  }
};

/// "zigzag" or "displacement"; anything else is an InputError naming `what` (option or key).
TransportMode parse_expected_mode(const std::string& text, const std::string& what);

struct DiluteModeEntry {
  double row_shift_um = 0, capillary_number = 0;
  TransportMode mode = TransportMode::kMixed;  ///< kMixed / kUndecided: not known
  std::string source;
};

/// Reads a dilute-limit map; unknown keys, missing keys and bad mode strings are InputErrors with
/// file, line and key.
std::vector<DiluteModeEntry> read_dilute_modes(const std::string& path);

/// The entry for (d, Ca) (equal within 1e-6 relative); an unknown mode when there is none.
ExpectedMode lookup_expected_mode(const std::vector<DiluteModeEntry>& map, const std::string& file,
                                  double d_um, std::optional<double> capillary_number);

}  // namespace dld::analysis
