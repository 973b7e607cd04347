// SPDX-License-Identifier: MIT
#pragma once
#include <fmt/format.h>

#include <string>

#include "shared/scene.hpp"

namespace dld::fluid::testing {

/// The DLD cell of SPEC section 2 at lattice spacing dx_um and row shift d_um (target Re 0.1).
inline Scene dld_scene(double dx_um, double d_um, const std::string& collision = "trt",
                       double reynolds = 0.1, const std::string& wall_rule = "bounce_back") {
  return parse_scene(fmt::format(R"(
[scene]
name = "test-dld"
[geometry]
pillar_radius_um = 10.0
pillar_spacing_um = 32.0
depth_um = 4.8
row_shift_um = {}
[lattice]
dx_um = {}
collision = "{}"
wall_rule = "{}"
[drive]
reynolds = {}
[run]
steady_tolerance = 1e-10
log_every = 500
max_steps = 60000
)",
                                 d_um, dx_um, collision, wall_rule, reynolds),
                     "test-dld.toml");
}

}  // namespace dld::fluid::testing
