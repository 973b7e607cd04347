// SPDX-License-Identifier: MIT
#include "membrane/spring_network.hpp"

#include <fmt/format.h>

#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {

SpringNetwork::SpringNetwork(const TriMesh& reference, const SpringParams& p)
    : p_(p), edges_(edges(reference)) {
  if (!(p.k >= 0.0) || !std::isfinite(p.k))
    throw InputError(fmt::format("springs model: k must be >= 0, got {}", p.k));
  rest_.reserve(edges_.size());
  for (const auto& [i, j] : edges_)
    rest_.push_back((reference.nodes.col(i) - reference.nodes.col(j)).norm());
}

double SpringNetwork::energy(const Eigen::Ref<const Points>& x) const {
  double e = 0.0;
  for (std::size_t s = 0; s < edges_.size(); ++s) {
    const double dl = (x.col(edges_[s][0]) - x.col(edges_[s][1])).norm() - rest_[s];
    e += 0.5 * p_.k * dl * dl;
  }
  return e;
}

double SpringNetwork::add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
  double e = 0.0;
  for (std::size_t s = 0; s < edges_.size(); ++s) {
    const auto [i, j] = edges_[s];
    const Eigen::Vector3d d = x.col(i) - x.col(j);
    const double l = d.norm(), dl = l - rest_[s];
    e += 0.5 * p_.k * dl * dl;
    // -dE/dx_i = -k (l - l0) d / l; node j gets the opposite.
    const Eigen::Vector3d fi = -p_.k * dl / l * d;
    f.col(i) += fi;
    f.col(j) -= fi;
  }
  return e;
}

SpringNetwork SpringNetwork::from_scene(const std::optional<TomlSection>& t,
                                        const ModelContext& c) {
  const double rel = required_table(t, kName).in_range("modulus_rel", 0.0, 1e9);
  return SpringNetwork(c.reference, {rel * c.kappa_s_lu});
}

SpringNetwork SpringNetwork::for_test(const TriMesh& reference) {
  return SpringNetwork(reference, {1.0});
}

std::string SpringNetwork::describe() const {
  return fmt::format("springs: k {:.6g} (lattice modulus), {} edges", p_.k, edges_.size());
}

}  // namespace dld::membrane
