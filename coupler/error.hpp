// SPDX-License-Identifier: MIT
#pragma once
#include "shared/input_error.hpp"

namespace dld::coupler {

/// A coupling failure the user must see (handshake mismatch, malformed frame, peer timeout, error
/// reported by the peer). The message is one line naming the side, the step and the field.
/// Derives from InputError so programs print it and exit non-zero like any other user error.
class CouplerError : public dld::InputError {
 public:
  using dld::InputError::InputError;
};

}  // namespace dld::coupler
