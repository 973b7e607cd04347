// SPDX-License-Identifier: MIT
// Fills the ghost layer of a population array before streaming: periodic y, shifted periodic x
// (exact copy for a whole-node shift, linear interpolation along y otherwise, which keeps the
// total of every population: each source value is split with weights summing to one), and
// periodic z when the box has no z walls. Only the populations that cross each face are copied.
#pragma once
#include "fluid/lattice.hpp"
#include "fluid/population_view.hpp"

namespace dld::fluid {

void fill_periodic_ghosts(const Lattice& lattice, double* f);
/// The same through a view (fluid/population_view.hpp): pull-layout slot (q, s) at v(q, s).
void fill_periodic_ghosts(const Lattice& lattice, const PopulationView& v);

}  // namespace dld::fluid
