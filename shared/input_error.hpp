// SPDX-License-Identifier: MIT
#pragma once
#include <stdexcept>
#include <string>

namespace dld {

/// A user error (bad scene, mesh, command-line value, protocol frame): the message is one line
/// that names the file, key or field and what was expected. Programs print it and exit non-zero.
/// Broken internal invariants are asserts, not InputErrors.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace dld
