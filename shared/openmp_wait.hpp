// SPDX-License-Identifier: MIT
#pragma once
#include <cstdlib>
#include <string>

namespace dld {
/// How this program's OpenMP threads wait between parallel regions, for its log: the variables
/// dld-run sets (docs/performance.md, "A short spin before sleeping") or the user's values.
inline std::string openmp_wait_settings() {
  std::string s;
  for (const char* name : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT"}) {
    const char* value = std::getenv(name);
    s += std::string(s.empty() ? "" : ", ") + name + " " + (value ? value : "unset");
  }
  return s;
}
}  // namespace dld
