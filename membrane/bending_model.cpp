// SPDX-License-Identifier: MIT
#include "membrane/bending_model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const double kSqrt3 = std::sqrt(3.0);

/// theta - theta0 from y = r sin(theta), x = r cos(theta) and theta0's cosine and sine: the
/// angle of (x, y) rotated by -theta0. A membrane bends little per hinge, so the rotated angle is
/// small: |tan| <= 1/4 takes the Taylor series of atan (terms to t^25, truncation below 1e-17
/// relative), which costs a division and a polynomial instead of an atan2 (42 of the 115 ns a
/// hinge took). Larger deviations take atan2 as before. Both agree to round-off.
double angle_deviation(double y, double x, double theta0, double c0, double s0) {
  const double sn = y * c0 - x * s0, cs = x * c0 + y * s0;
  if (cs > 0.0 && 4.0 * std::abs(sn) <= cs) {
    const double t = sn / cs, t2 = t * t;
    constexpr double c[13] = {1.0,       -1.0 / 3,  1.0 / 5,   -1.0 / 7, 1.0 / 9,
                              -1.0 / 11, 1.0 / 13,  -1.0 / 15, 1.0 / 17, -1.0 / 19,
                              1.0 / 21,  -1.0 / 23, 1.0 / 25};  // atan t = t sum c_n t^2n
    double p = c[12];
    for (int n = 11; n >= 0; --n) p = c[n] + t2 * p;
    return t * p;
  }
  return std::atan2(y, x) - theta0;
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
  static thread_local Eigen::Matrix3Xd scratch;  // per calling thread, shared by the loop
  scratch.resize(3, 4 * Eigen::Index{n});
  Eigen::Matrix3Xd& slot = scratch;
  double en = 0.0;
#pragma omp parallel for reduction(+ : en) schedule(static) if (n > 8192)
  for (int k = 0; k < n; ++k) {
    const Hinge& h = hinges_[k];
    const Eigen::Vector3d a = x.col(h.a);
    const Eigen::Vector3d e = x.col(h.b) - a, ca = x.col(h.c) - a, da = x.col(h.d) - a;
    const Eigen::Vector3d n1 = e.cross(ca), n2 = da.cross(e);
    const double le2 = e.squaredNorm();
    const double le = std::sqrt(le2), inv_le = 1.0 / le;
    // atan2 is scale-free: (n1 x n2).e / |e| against n1.n2, both multiplied by |e|.
    const double dt =
        angle_deviation(n1.cross(n2).dot(e), n1.dot(n2) * le, theta0_[k], cos0_[k], sin0_[k]);
    en += dt * dt;
    // Gradient of theta (Bridson et al. 2003): wing nodes along their face normals, edge nodes
    // such that the four gradients sum to zero and carry no torque. (c - b).e = (c - a).e - |e|^2.
    const double scale = -2.0 * kSqrt3 * p_.kappa_b * dt;  // force = -dE/dtheta * grad theta
    const Eigen::Vector3d u1 = (scale / n1.squaredNorm()) * n1,
                          u2 = (scale / n2.squaredNorm()) * n2;
    const double pc = ca.dot(e) * inv_le, pd = da.dot(e) * inv_le;
    const Eigen::Index base = 4 * Eigen::Index{k};
    slot.col(base) = -((pc - le) * u1 + (pd - le) * u2);
    slot.col(base + 1) = pc * u1 + pd * u2;
    slot.col(base + 2) = -le * u1;
    slot.col(base + 3) = -le * u2;
  }
  gather_.add(slot, f);
  return kSqrt3 * p_.kappa_b * en;
}

}  // namespace dld::membrane
