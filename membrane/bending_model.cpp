// SPDX-License-Identifier: MIT
#include "membrane/bending_model.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
const double kSqrt3 = std::sqrt(3.0);
}

BendingModel::BendingModel(const TriMesh& reference, const BendingParams& p)
    : p_(p), hinges_(hinges(reference)) {
  if (!(p.kappa_b >= 0.0) || !std::isfinite(p.kappa_b))
    throw InputError(fmt::format("bending model: kappa_b must be >= 0, got {}", p.kappa_b));
  std::vector<int> corners;
  for (const Hinge& h : hinges_) {
    theta0_.push_back(angle(h, reference.nodes));
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

double BendingModel::add_forces(const Eigen::Ref<const Points>& x, Eigen::Ref<Points> f) const {
  const int n = static_cast<int>(hinges_.size());
  static thread_local Eigen::Matrix3Xd scratch;  // per calling thread, shared by the loop
  scratch.resize(3, 4 * n);
  Eigen::Matrix3Xd& slot = scratch;
  double en = 0.0;
#pragma omp parallel for reduction(+ : en) schedule(static) if (n > 8192)
  for (int k = 0; k < n; ++k) {
    const Hinge& h = hinges_[k];
    const Eigen::Vector3d a = x.col(h.a), b = x.col(h.b), c = x.col(h.c), d = x.col(h.d);
    const Eigen::Vector3d e = b - a;
    const Eigen::Vector3d n1 = e.cross(c - a), n2 = (d - a).cross(e);
    const double le = e.norm();
    const double theta = std::atan2(n1.cross(n2).dot(e) / le, n1.dot(n2));
    const double dt = theta - theta0_[k];
    en += dt * dt;
    // Gradient of theta (Bridson et al. 2003): wing nodes along their face normals, edge nodes
    // such that the four gradients sum to zero and carry no torque.
    const Eigen::Vector3d u1 = n1 / n1.squaredNorm(), u2 = n2 / n2.squaredNorm();
    const Eigen::Vector3d gc = -le * u1;
    const Eigen::Vector3d gd = -le * u2;
    const Eigen::Vector3d ga = -((c - b).dot(e) / le * u1 + (d - b).dot(e) / le * u2);
    const Eigen::Vector3d gb = ((c - a).dot(e) / le * u1 + (d - a).dot(e) / le * u2);
    const double scale = -2.0 * kSqrt3 * p_.kappa_b * dt;  // force = -dE/dtheta * grad theta
    slot.col(4 * k) = scale * ga;
    slot.col(4 * k + 1) = scale * gb;
    slot.col(4 * k + 2) = scale * gc;
    slot.col(4 * k + 3) = scale * gd;
  }
  gather_.add(slot, f);
  return kSqrt3 * p_.kappa_b * en;
}

}  // namespace dld::membrane
