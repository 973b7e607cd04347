// SPDX-License-Identifier: MIT
#include "membrane/area_penalty.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {

AreaPenalty::AreaPenalty(const TriMesh& reference, const AreaParams& p)
    : p_(p), faces_(reference.faces), a0_(surface_area(reference)) {
  if (!(p.kappa_a >= 0.0) || !std::isfinite(p.kappa_a))
    throw InputError(fmt::format("area model: kappa_A must be >= 0, got {}", p.kappa_a));
}

double AreaPenalty::area(const Eigen::Ref<const Points>& x) const {
  double a = 0.0;
  for (const Face& t : faces_)
    a += 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).norm();
  return a;
}

double AreaPenalty::energy(const Eigen::Ref<const Points>& x) const {
  const double da = area(x) - a0_;
  return 0.5 * p_.kappa_a * da * da / a0_;
}

double AreaPenalty::add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
  const double da = area(x) - a0_;
  const double s = -p_.kappa_a * da / a0_;
  // dA/dx_i = (1/2) n_hat x (x_{i+2} - x_{i+1}) for a counter-clockwise triangle.
  for (const Face& t : faces_) {
    const Eigen::Vector3d n =
        (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0])).normalized();
    for (int k = 0; k < 3; ++k)
      f.col(t[k]) += s * 0.5 * n.cross(x.col(t[(k + 2) % 3]) - x.col(t[(k + 1) % 3]));
  }
  return 0.5 * p_.kappa_a * da * da / a0_;
}

AreaPenalty AreaPenalty::from_scene(const std::optional<TomlSection>& t, const ModelContext& c) {
  const double rel = required_table(t, kName).in_range("modulus_rel", 0.0, 1e9);
  return AreaPenalty(c.reference, {rel * c.kappa_s_lu});
}

AreaPenalty AreaPenalty::for_test(const TriMesh& reference) {
  return AreaPenalty(reference, {1.0});
}

std::string AreaPenalty::describe() const {
  return fmt::format("area: kappa_A {:.6g} (lattice modulus)", params().kappa_a);
}

}  // namespace dld::membrane
