// SPDX-License-Identifier: MIT
// Half-way bounce-back on resting walls (pillar, z walls): before the pull, each solid slot that a
// fluid node will read receives that node's own opposite post-collision population, so the wall
// sits half-way between the fluid and the solid node (Ladd 1994; Krueger et al., The Lattice
// Boltzmann Method, 2017, sec. 5.3.3).
#pragma once
#include "fluid/lattice.hpp"

namespace dld::fluid {

void apply_bounce_back(const Lattice& lattice, double* f);

}  // namespace dld::fluid
