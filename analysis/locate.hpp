// SPDX-License-Identifier: MIT
// Files of the source tree that dld-analyze needs at run time (plot scripts, the dilute-limit map),
// found beside the executable's tree or in the source tree it was built from.
#pragma once
#include <string>
#include <vector>

namespace dld::analysis {

/// The first existing `root/relative` over the roots: the executable's directory and its two
/// parents (build/analysis/dld-analyze -> the repository), then `source_dir`. Empty if none.
std::string locate_source_file(const std::string& relative, const std::string& source_dir);

/// Runs `argv[0]` with the arguments (no shell) and waits; returns its exit status (127 when it
/// cannot be started, 128 + signal when killed).
int run_program(const std::vector<std::string>& argv);

}  // namespace dld::analysis
