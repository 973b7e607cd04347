// SPDX-License-Identifier: MIT
// A program's main: runs its body and turns any exception that escapes the body's own handlers
// into one error line and exit code 1, never a crash (std::terminate).
#pragma once
#include <cstdio>
#include <exception>

namespace dld {

inline int guarded_main(const char* program, int (*body)(int, char**), int argc, char** argv) {
  try {
    return body(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 1;
  }
}

}  // namespace dld
