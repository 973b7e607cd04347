// SPDX-License-Identifier: MIT
// Box frame -> device frame for a sampled trajectory (SPEC section 7). A point folded into the
// lambda x lambda box jumps by about lambda when it crosses a face; each such jump is one boundary
// crossing: through x = lambda the device x grows by lambda and the frame moves up by d (the next
// column's pillar sits d higher), through y = lambda the device y grows by lambda; crossings back
// count negatively. Needs samples closer than lambda/2 in x and y.
#pragma once
#include <array>
#include <vector>

#include "shared/dld_geometry.hpp"

namespace dld::analysis {

/// Device coordinates [cell's units] of box-frame samples; the first sample is taken as it is
/// (zero crossings).
std::vector<std::array<double, 3>> unwrap_box_trajectory(
    const DldCell& cell, const std::vector<std::array<double, 3>>& box);

}  // namespace dld::analysis
