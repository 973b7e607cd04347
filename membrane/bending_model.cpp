// SPDX-License-Identifier: MIT
#include "membrane/bending_model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const double kSqrt3 = std::sqrt(3.0);

/// Forces on the four nodes of one hinge (12 values, nodes a, b, c, d) and its deviation from the
/// rest angle. The deviation is the angle of (x, y) = r (cos theta, sin theta) rotated by -theta0.
/// A membrane bends little per hinge, so that angle is small: with |tan| <= 1/4 it is the Taylor
/// series of atan (to t^25, truncation below 1e-17 relative), a division and a polynomial that
/// vectorise, instead of an atan2 (42 of the 115 ns a hinge took). With kSmallOnly a larger
/// deviation returns false and leaves the slots unset (the caller redoes that hinge); otherwise
/// it takes atan2 as before. Both agree to round-off.
template <bool kSmallOnly>
inline bool hinge_forces(const Hinge& h, double theta0, double c0, double s0, const double* X,
                         Eigen::Index stride, double k2, double* slot, double& dt) {
  const double* pa = X + h.a * stride;
  const double* pb = X + h.b * stride;
  const double* pc = X + h.c * stride;
  const double* pd = X + h.d * stride;
  const double e[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  const double ca[3] = {pc[0] - pa[0], pc[1] - pa[1], pc[2] - pa[2]};
  const double da[3] = {pd[0] - pa[0], pd[1] - pa[1], pd[2] - pa[2]};
  const double n1[3] = {e[1] * ca[2] - e[2] * ca[1], e[2] * ca[0] - e[0] * ca[2],
                        e[0] * ca[1] - e[1] * ca[0]};  // face a-b-c
  const double n2[3] = {da[1] * e[2] - da[2] * e[1], da[2] * e[0] - da[0] * e[2],
                        da[0] * e[1] - da[1] * e[0]};  // face b-a-d
  const double le2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
  const double le = std::sqrt(le2), inv_le = 1.0 / le;
  // atan2 is scale-free: (n1 x n2).e / |e| against n1.n2, both multiplied by |e|.
  const double m[3] = {n1[1] * n2[2] - n1[2] * n2[1], n1[2] * n2[0] - n1[0] * n2[2],
                       n1[0] * n2[1] - n1[1] * n2[0]};
  const double y = m[0] * e[0] + m[1] * e[1] + m[2] * e[2];
  const double x = (n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2]) * le;
  const double sn = y * c0 - x * s0, cs = x * c0 + y * s0;
  const bool small = cs > 0.0 && 4.0 * std::abs(sn) <= cs;
  if (small) {
    const double t = sn / cs, t2 = t * t;
    constexpr double c[13] = {1.0,       -1.0 / 3,  1.0 / 5,   -1.0 / 7, 1.0 / 9,
                              -1.0 / 11, 1.0 / 13,  -1.0 / 15, 1.0 / 17, -1.0 / 19,
                              1.0 / 21,  -1.0 / 23, 1.0 / 25};  // atan t = t sum c_n t^2n
    double p = c[12];
    for (int q = 11; q >= 0; --q) p = c[q] + t2 * p;
    dt = t * p;
  } else if (kSmallOnly) {
    dt = 0.0;
    return false;
  } else {
    dt = std::atan2(y, x) - theta0;
  }
  // Gradient of theta (Bridson et al. 2003): wing nodes along their face normals, edge nodes
  // such that the four gradients sum to zero and carry no torque. (c - b).e = (c - a).e - |e|^2.
  const double scale = k2 * dt;  // force = -dE/dtheta * grad theta
  const double s1 = scale / (n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
  const double s2 = scale / (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
  const double pcv = (ca[0] * e[0] + ca[1] * e[1] + ca[2] * e[2]) * inv_le;
  const double pdv = (da[0] * e[0] + da[1] * e[1] + da[2] * e[2]) * inv_le;
  for (int a = 0; a < 3; ++a) {
    const double u1 = s1 * n1[a], u2 = s2 * n2[a];
    slot[a] = -((pcv - le) * u1 + (pdv - le) * u2);
    slot[3 + a] = pcv * u1 + pdv * u2;
    slot[6 + a] = -le * u1;
    slot[9 + a] = -le * u2;
  }
  return true;
}
}  // namespace

BendingModel::BendingModel(const TriMesh& reference, const BendingParams& p)
    : p_(p), hinges_(hinges(reference)) {
  if (!(p.kappa_b >= 0.0) || !std::isfinite(p.kappa_b))
    throw InputError(fmt::format("bending model: kappa_b must be >= 0, got {}", p.kappa_b));
  std::vector<int> corners;
  for (const Hinge& h : hinges_) {
    theta0_.push_back(angle(h, reference.nodes));
    cos0_.push_back(std::cos(theta0_.back()));
    sin0_.push_back(std::sin(theta0_.back()));
    corners.insert(corners.end(), {h.a, h.b, h.c, h.d});
  }
  gather_ = NodeGather(corners, reference.node_count());
}

double BendingModel::angle(const Hinge& h, const Eigen::Ref<const Points>& x) {
  const Eigen::Vector3d e = x.col(h.b) - x.col(h.a);
  const Eigen::Vector3d n1 = e.cross(x.col(h.c) - x.col(h.a));    // face a-b-c
  const Eigen::Vector3d n2 = (x.col(h.d) - x.col(h.a)).cross(e);  // face b-a-d
  return std::atan2(n1.cross(n2).dot(e) / e.norm(), n1.dot(n2));
}

double BendingModel::energy(const Eigen::Ref<const Points>& x) const {
  double en = 0.0;
  const int n = static_cast<int>(hinges_.size());
#pragma omp parallel for reduction(+ : en) schedule(static) if (n > 8192)
  for (int k = 0; k < n; ++k) {
    const double d = angle(hinges_[k], x) - theta0_[k];
    en += d * d;
  }
  return kSqrt3 * p_.kappa_b * en;
}

// Eigen::Ref by value is Eigen's idiom for a writable view (cheap to copy into NodeGather::add).
// NOLINTNEXTLINE(performance-unnecessary-value-param)
double BendingModel::add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
  const int n = static_cast<int>(hinges_.size());
  static thread_local Eigen::Matrix3Xd scratch;        // per calling thread: 4 slots per hinge
  static thread_local std::vector<std::uint8_t> bent;  // hinges for the atan2 path
  scratch.resize(3, 4 * Eigen::Index{n});
  bent.resize(static_cast<std::size_t>(n));
  double* slot = scratch.data();
  const double* X = x.data();
  const Eigen::Index stride = x.outerStride();
  const Hinge* h = hinges_.data();
  const double *th0 = theta0_.data(), *c0 = cos0_.data(), *s0 = sin0_.data();
  std::uint8_t* big = bent.data();
  const double k2 = -2.0 * kSqrt3 * p_.kappa_b;
  double en = 0.0;
  // One hinge per SIMD lane; the few bent beyond atan(1/4) from rest are redone below.
#pragma omp simd reduction(+ : en)
  for (int k = 0; k < n; ++k) {
    double dt = 0.0;
    big[k] = hinge_forces<true>(h[k], th0[k], c0[k], s0[k], X, stride, k2,
                                slot + 12 * std::ptrdiff_t{k}, dt)
                 ? 0
                 : 1;
    en += dt * dt;
  }
  for (int k = 0; k < n; ++k) {
    if (!big[k]) continue;
    double dt = 0.0;
    hinge_forces<false>(h[k], th0[k], c0[k], s0[k], X, stride, k2, slot + 12 * std::ptrdiff_t{k},
                        dt);
    en += dt * dt;
  }
  gather_.add(scratch, f);
  return kSqrt3 * p_.kappa_b * en;
}

BendingModel BendingModel::from_scene(const std::optional<TomlSection>& t, const ModelContext& c) {
  const TomlSection& s = required_table(t, kName);
  const bool rel = s.has("modulus_rel"), joule = s.has("modulus_J");
  if (rel == joule)
    s.fail(
        rel ? "modulus_rel" : "modulus_J",
        "give exactly one of modulus_rel (kappa_b / (kappa_s r^2)) and modulus_J (kappa_b in J)");
  if (joule)
    return BendingModel(c.reference, {s.in_range("modulus_J", 0.0, 1e-15) * c.energy_to_lu});
  return BendingModel(c.reference, {s.in_range("modulus_rel", 0.0, 1e3) * c.kappa_s_lu *
                                    c.radius_lu * c.radius_lu});
}

BendingModel BendingModel::for_test(const TriMesh& reference) {
  return BendingModel(reference, {1.0});
}

std::string BendingModel::describe() const {
  return fmt::format("bending: kappa_b {:.6g} (lattice energy)", params().kappa_b);
}

}  // namespace dld::membrane
