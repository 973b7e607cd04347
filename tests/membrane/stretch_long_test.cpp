// SPDX-License-Identifier: MIT
// The 2000-face optical-tweezers run against Mills et al. 2004 (label "long").
#include "stretch_common.hpp"

TEST(OpticalTweezers, Cell2000FacesInsideMills2004Ranges) {
  dld::membrane::test::check_against_mills("stretch_mills2004.toml", 2000);
}
