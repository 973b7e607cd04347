// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include <cmath>

#include "shared/units.hpp"

namespace {

TEST(LatticeUnits, TimeStepFollowsFromViscosity) {
  // dx = 0.4 um, tau = 1 (nu_lu = 1/6), nu = 1e-6 m^2/s: dt = nu_lu dx^2 / nu.
  const dld::LatticeUnits u(0.4e-6, 1.0, 1e-6, 1000.0);
  EXPECT_NEAR(u.dt_s(), (1.0 / 6.0) * 0.16e-12 / 1e-6, 1e-22);
  EXPECT_NEAR(u.nu_lu(), 1.0 / 6.0, 1e-15);
}

TEST(LatticeUnits, ConversionsRoundTripAndAgreeDimensionally) {
  const dld::LatticeUnits u(0.5e-6, 0.8, 1.2e-6, 1025.0);
  EXPECT_NEAR(u.velocity_m_s(u.velocity_lu(3e-3)), 3e-3, 1e-15);
  EXPECT_NEAR(u.force_density_n_m3(u.force_density_lu(2e6)), 2e6, 1e-6);
  EXPECT_NEAR(u.modulus_n_m(u.modulus_lu(5.3e-6)), 5.3e-6, 1e-18);
  // A force density times a volume is a force: f_lu * 1 node = F_lu.
  const double f = 7e5;
  EXPECT_NEAR(u.force_lu(f * std::pow(u.dx_m(), 3)), u.force_density_lu(f),
              1e-12 * u.force_density_lu(f));
  // A modulus times a length is a force.
  EXPECT_NEAR(u.force_lu(5e-6 * u.dx_m()), u.modulus_lu(5e-6), 1e-12 * u.modulus_lu(5e-6));
}

}  // namespace
