// SPDX-License-Identifier: MIT
// The DLD scene the unit tests and benchmarks start from: SPEC section 2's cell (pillar radius
// 10 um, spacing 32 um, depth 4.8 um, d = 4.4 um) at dx 0.4 um and Re 0.1. One text, so that a key
// renamed in the scene reader is renamed once; tests change it with their own replacements.
#pragma once

namespace dld::testing {

inline constexpr const char* kBaseScene = R"(
[scene]
name = "t"
[geometry]
pillar_radius_um = 10.0
pillar_spacing_um = 32.0
depth_um = 4.8
row_shift_um = 4.4
[lattice]
dx_um = 0.4
[drive]
reynolds = 0.1
)";

}  // namespace dld::testing
