// SPDX-License-Identifier: MIT
#include "membrane/volume_penalty.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {

VolumePenalty::VolumePenalty(const TriMesh& reference, const VolumeParams& p)
    : p_(p), faces_(reference.faces), v0_(enclosed_volume(reference)) {
  if (!(p.kappa_v >= 0.0) || !std::isfinite(p.kappa_v))
    throw InputError(fmt::format("volume model: kappa_V must be >= 0, got {}", p.kappa_v));
  if (!(v0_ > 0.0))
    throw InputError("volume model: the reference mesh encloses no positive volume");
}

double VolumePenalty::volume(const Eigen::Ref<const Points>& x) const {
  double v = 0.0;
  for (const Face& t : faces_) v += x.col(t[0]).dot(x.col(t[1]).cross(x.col(t[2])));
  return v / 6.0;
}

double VolumePenalty::energy(const Eigen::Ref<const Points>& x) const {
  const double dv = volume(x) - v0_;
  return 0.5 * p_.kappa_v * dv * dv / v0_;
}

double VolumePenalty::add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
  const double dv = volume(x) - v0_;
  // dV/dx0 = (x1 x x2)/6 and cyclically.
  const double s = -p_.kappa_v * dv / v0_ / 6.0;
  for (const Face& t : faces_) {
    f.col(t[0]) += s * x.col(t[1]).cross(x.col(t[2]));
    f.col(t[1]) += s * x.col(t[2]).cross(x.col(t[0]));
    f.col(t[2]) += s * x.col(t[0]).cross(x.col(t[1]));
  }
  return 0.5 * p_.kappa_v * dv * dv / v0_;
}

VolumePenalty VolumePenalty::from_scene(const std::optional<TomlSection>& t,
                                        const ModelContext& c) {
  const TomlSection& s = required_table(t, kName);
  const double rel = s.in_range("modulus_rel", 0.0, 1e9);
  // kappa_V relative to the kappa_s of another Ca: the same kappa_V at every Ca of a sweep (kappa_s
  // falls as 1/Ca at fixed drive), where a stiffness that follows kappa_s would weaken 5-fold
  // from Ca 0.2 to 1.0.
  double kappa_s = c.kappa_s_lu;
  if (s.has("reference_capillary_number")) {
    const double ref = s.positive("reference_capillary_number");
    if (!(c.capillary_number > 0.0)) {
      s.fail("reference_capillary_number",
             "needs [membrane] capillary_number (kappa_s was given directly)");
    }
    kappa_s *= c.capillary_number / ref;
  }
  return VolumePenalty(c.reference, {rel * kappa_s / c.radius_lu});
}

VolumePenalty VolumePenalty::for_test(const TriMesh& reference) {
  return VolumePenalty(reference, {1.0});
}

std::string VolumePenalty::describe() const {
  return fmt::format("volume: kappa_V {:.6g} (lattice energy/volume), V0 {:.6g}", params().kappa_v,
                     reference_volume());
}

}  // namespace dld::membrane
