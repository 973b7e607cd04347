// SPDX-License-Identifier: MIT
#include "shared/units.hpp"

#include <cassert>

namespace dld {

LatticeUnits::LatticeUnits(double dx_m, double tau, double nu_m2_s, double rho_kg_m3)
    : dx_(dx_m), rho_(rho_kg_m3), nu_lu_((tau - 0.5) / 3.0) {
  assert(dx_m > 0 && tau > 0.5 && nu_m2_s > 0 && rho_kg_m3 > 0);
  dt_ = nu_lu_ * dx_m * dx_m / nu_m2_s;
}

}  // namespace dld
