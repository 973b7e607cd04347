// SPDX-License-Identifier: MIT
#include "fluid/bounce_back.hpp"

namespace dld::fluid {

void apply_bounce_back(const Lattice& lattice, double* f) {
  const auto& links = lattice.links();
  const std::size_t count = links.size();
#pragma omp parallel for schedule(static)
  for (std::size_t l = 0; l < count; ++l) f[links[l].target] = f[links[l].source];
}

}  // namespace dld::fluid
