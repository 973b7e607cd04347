// SPDX-License-Identifier: MIT
// Half-way bounce-back on resting walls (pillar, z walls): before the pull, each solid slot that a
// fluid node will read receives that node's own opposite post-collision population, so the wall
// sits half-way between the fluid and the solid node (Ladd 1994; Krueger et al., The Lattice
// Boltzmann Method, 2017, sec. 5.3.3).
#pragma once
#include <span>
#include <vector>

#include "fluid/lattice.hpp"
#include "fluid/population_view.hpp"

namespace dld::fluid {

void apply_bounce_back(const Lattice& lattice, double* f);

/// The lattice's links with their slots where a view puts them (indices from `f`), for the
/// in-place update's two states (fluid/population_view.hpp); computed once per state.
struct BounceBackTables {
  std::vector<BounceBackLink> links;
  std::vector<CurvedLink> curved;
};
BounceBackTables map_bounce_back(const Lattice& lattice, const PopulationView& v, const double* f);
/// Bounce-back with links mapped for the view v of f (the pull layout: the lattice's own links).
void apply_bounce_back(const Lattice& lattice, std::span<const BounceBackLink> links,
                       std::span<const CurvedLink> curved, const PopulationView& v, double* f);

}  // namespace dld::fluid
