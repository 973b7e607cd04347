// SPDX-License-Identifier: MIT
#include "membrane/volume_correction.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace dld::membrane {
namespace {

/// V = (1/6) sum_f x_a . (x_b x x_c) about the centroid c (the same V; less round-off far from
/// the origin), and with g its gradient dV/dx_i = (1/6) sum over i's faces of the opposite cross.
double volume_and_gradient(const Eigen::Ref<const Points>& x, const std::vector<Face>& faces,
                           const Eigen::Vector3d& c, Points* g) {
  double v = 0.0;
  if (g != nullptr) g->setZero(3, x.cols());
  for (const Face& t : faces) {
    const Eigen::Vector3d a = x.col(t[0]) - c, b = x.col(t[1]) - c, d = x.col(t[2]) - c;
    v += a.dot(b.cross(d));
    if (g == nullptr) continue;
    g->col(t[0]) += b.cross(d);
    g->col(t[1]) += d.cross(a);
    g->col(t[2]) += a.cross(b);
  }
  if (g != nullptr) *g /= 6.0;
  return v / 6.0;
}

}  // namespace

double restore_volume(Eigen::Ref<Points> x, const std::vector<Face>& faces, double v0) {
  const Eigen::Vector3d c = x.rowwise().mean();
  Points g, g_at;
  const double v_start = volume_and_gradient(x, faces, c, &g);
  // Newton on V(x + lambda g) = V0 along the start's gradient g (a cubic in lambda, its slope
  // g . dV/dx at the point reached): two or three steps for the changes of a fraction of a per
  // cent met in a run, a few more for the per cents of the tests. 1e-13 V0 is near the round-off
  // of the sum over a few thousand faces.
  double v = v_start, lambda = 0.0;
  for (int it = 0; it < 10 && std::abs(v - v0) > 1e-13 * v0; ++it) {
    const double slope = it == 0 ? g.squaredNorm() : (g.array() * g_at.array()).sum();
    const double step = (v0 - v) / slope;
    if (!std::isfinite(step) || step == 0.0) break;
    lambda += step;
    v = volume_and_gradient(x + lambda * g, faces, c, &g_at);
  }
  if (lambda == 0.0 || !std::isfinite(v)) return 0.0;
  x += lambda * g;
  return (v - v_start) / v0;  // what was given back, also where Newton stopped short
}

}  // namespace dld::membrane
