// SPDX-License-Identifier: MIT
#include "membrane/bending_model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const double kSqrt3 = std::sqrt(3.0);

/// Forces on the four nodes of one hinge (12 values; its nodes a, b, c, d at `corner`, each
/// `stride` values apart in X) and its deviation from the rest angle, the angle of (x, y) = r (cos
/// theta, sin theta) rotated by -theta0. A membrane bends little per hinge, so that angle is small:
/// with |tan| <= 1/4 it is the Taylor series of atan (to t^25, truncation below 1e-17 relative), a
/// division and a polynomial that vectorise, instead of an atan2 (42 of the 115 ns a hinge took).
/// With kSmallOnly a larger deviation counts as zero (slots written with zero forces) and the
/// return value is false: the caller redoes that hinge. Otherwise it takes atan2 there. Both agree
/// to round-off. Branch-free (selects, not jumps), so that GCC vectorises the kSmallOnly loop.
template <bool kSmallOnly>
inline bool hinge_forces(const int* corner, int stride, double theta0, double c0, double s0,
                         const double* X, double k2, double* slot, double& dt) {
  // 32-bit offsets: GCC 12 gathers with those only (with 64-bit ones this loop stayed scalar).
  const int a = corner[0] * stride, b = corner[1] * stride, c = corner[2] * stride,
            d = corner[3] * stride;
  const double e[3] = {X[b] - X[a], X[b + 1] - X[a + 1], X[b + 2] - X[a + 2]};
  const double ca[3] = {X[c] - X[a], X[c + 1] - X[a + 1], X[c + 2] - X[a + 2]};
  const double da[3] = {X[d] - X[a], X[d + 1] - X[a + 1], X[d + 2] - X[a + 2]};
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
  const bool small = (cs > 0.0) & (4.0 * std::abs(sn) <= cs);            // & : no branch
  const double t = (small ? sn : 0.0) / (small ? cs : 1.0), t2 = t * t;  // sn / cs if small
  constexpr double cn[13] = {1.0,       -1.0 / 3,  1.0 / 5,   -1.0 / 7, 1.0 / 9,
                             -1.0 / 11, 1.0 / 13,  -1.0 / 15, 1.0 / 17, -1.0 / 19,
                             1.0 / 21,  -1.0 / 23, 1.0 / 25};  // atan t = t sum c_n t^2n
  double p = cn[12];
  for (int q = 11; q >= 0; --q) p = cn[q] + t2 * p;
  if constexpr (kSmallOnly) {
    dt = small ? t * p : 0.0;
  } else {
    dt = small ? t * p : std::atan2(y, x) - theta0;
  }
  // Gradient of theta (Bridson et al. 2003): wing nodes along their face normals, edge nodes
  // such that the four gradients sum to zero and carry no torque. (c - b).e = (c - a).e - |e|^2.
  const double scale = k2 * dt;  // force = -dE/dtheta * grad theta
  const double s1 = scale / (n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
  const double s2 = scale / (n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
  const double pcv = (ca[0] * e[0] + ca[1] * e[1] + ca[2] * e[2]) * inv_le;
  const double pdv = (da[0] * e[0] + da[1] * e[1] + da[2] * e[2]) * inv_le;
  for (int q = 0; q < 3; ++q) {
    const double u1 = s1 * n1[q], u2 = s2 * n2[q];
    slot[q] = -((pcv - le) * u1 + (pdv - le) * u2);
    slot[3 + q] = pcv * u1 + pdv * u2;
    slot[6 + q] = -le * u1;
    slot[9 + q] = -le * u2;
  }
  return small;
}
}  // namespace

BendingModel::BendingModel(const TriMesh& reference, const BendingParams& p)
    : p_(p), hinges_(hinges(reference)) {
  if (!(p.kappa_b >= 0.0) || !std::isfinite(p.kappa_b))
    throw InputError(fmt::format("bending model: kappa_b must be >= 0, got {}", p.kappa_b));
  for (const Hinge& h : hinges_) {
    theta0_.push_back(angle(h, reference.nodes));
    cos0_.push_back(std::cos(theta0_.back()));
    sin0_.push_back(std::sin(theta0_.back()));
    corners_.insert(corners_.end(), {h.a, h.b, h.c, h.d});
  }
  gather_ = NodeGather(corners_, reference.node_count());
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
  // The corners in a plain array (from the Hinge structs this loop stayed scalar); a cell's
  // coordinates are far below 2^31 values.
  const auto stride = static_cast<int>(x.outerStride());
  const int* corner = corners_.data();
  const double *th0 = theta0_.data(), *c0 = cos0_.data(), *s0 = sin0_.data();
  std::uint8_t* big = bent.data();
  const double k2 = -2.0 * kSqrt3 * p_.kappa_b;
  double en = 0.0;
  // One hinge per SIMD lane; the few bent beyond atan(1/4) from rest are redone below.
#pragma omp simd reduction(+ : en)
  for (int k = 0; k < n; ++k) {
    double dt = 0.0;
    big[k] = static_cast<std::uint8_t>(!hinge_forces<true>(corner + 4 * std::ptrdiff_t{k}, stride,
                                                           th0[k], c0[k], s0[k], X, k2,
                                                           slot + 12 * std::ptrdiff_t{k}, dt));
    en += dt * dt;
  }
  for (int k = 0; k < n; ++k) {
    if (!big[k]) continue;
    double dt = 0.0;
    hinge_forces<false>(corner + 4 * std::ptrdiff_t{k}, stride, th0[k], c0[k], s0[k], X, k2,
                        slot + 12 * std::ptrdiff_t{k}, dt);
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
