// SPDX-License-Identifier: MIT
// Coarse-mesh optical-tweezers stretching of a healthy cell (G_s = 5.3 uN/m) against Mills et al.
// 2004: both diameters inside the experimental ranges at every force up to 193 pN.
#include "stretch_common.hpp"

TEST(OpticalTweezers, CoarseCellInsideMills2004Ranges) {
  dld::membrane::test::check_against_mills("stretch_mills2004.toml", 1000);
}
