// SPDX-License-Identifier: MIT
// What the two files of FluidSide share (fluid_side.cpp: the run; fluid_handshake.cpp: the
// hellos, their checks and the shared segments).
#pragma once
#include <chrono>

namespace dld::coupler::detail {

inline constexpr const char* kFluidSelf = "fluid";

inline double seconds(std::chrono::milliseconds t) {
  return static_cast<double>(t.count()) / 1000.0;
}

}  // namespace dld::coupler::detail
