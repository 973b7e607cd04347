// SPDX-License-Identifier: MIT
// What dld-analyze prints and writes: the terminal table and the three CSV files
// (<base>-cells.csv, <base>-summary.csv, <base>-outlets.csv). Lengths in um.
#pragma once
#include <string>

#include "analysis/run_analysis.hpp"
#include "analysis/run_file.hpp"

namespace dld::analysis {

/// "p_fZ", "p_fD", or "p_f" when the expected mode is unknown.
std::string failure_name(const ExpectedMode& expected);

/// Whether outlet 1..4 is where cells of the expected mode belong (O1, O2 zigzag; O3, O4
/// displacement); false when the mode is unknown.
bool correct_outlet(const ExpectedMode& expected, int outlet);

/// The terminal report: run facts, expected mode and its source, one line per cell, mean +- std,
/// outlet fractions.
std::string format_report(const Run& run, const RunAnalysis& a);

/// Writes the CSVs into `dir` (created if needed); returns their paths.
std::vector<std::string> write_csvs(const Run& run, const RunAnalysis& a, const std::string& dir,
                                    const std::string& base);

}  // namespace dld::analysis
