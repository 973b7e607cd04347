// SPDX-License-Identifier: MIT
#pragma once
#include <string>

namespace dld {
/// Sets up the default spdlog logger for a program: "[program] message" on stderr.
void setup_logging(const std::string& program, bool verbose = false);
}  // namespace dld
