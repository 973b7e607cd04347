// SPDX-License-Identifier: MIT
#include "membrane/evans_fung.hpp"

#include <algorithm>
#include <cmath>

namespace dld::membrane {

double EvansFungShape::half_thickness(double r) const {
  const double rho2 = (r / radius) * (r / radius);
  if (rho2 >= 1.0) return 0.0;
  return 0.5 * radius * std::sqrt(1.0 - rho2) * (c0 + c2 * rho2 + c4 * rho2 * rho2);
}

double EvansFungShape::implicit(double x, double y, double z) const {
  const double rho2 = (x * x + y * y) / (radius * radius);
  const double p = c0 + c2 * rho2 + c4 * rho2 * rho2;
  // (1 - rho^2) turns negative outside the rim, so f > 0 there for any z.
  return z * z - 0.25 * radius * radius * (1.0 - rho2) * p * p;
}

namespace {
// Substituting rho = sin(t) removes the square-root singularity at the rim: the integrands
// below are smooth in t, so composite Simpson converges fast.
template <class F>
double simpson(F f, double a, double b, int n = 20000) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
  return s * h / 3.0;
}
}  // namespace

double EvansFungShape::volume() const {
  // V = 2 * int_0^R 2 pi r z(r) dr, r = R sin t, dr = R cos t dt.
  auto f = [&](double t) {
    const double r = radius * std::sin(t);
    return 4.0 * M_PI * r * half_thickness(r) * radius * std::cos(t);
  };
  return simpson(f, 0.0, 0.5 * M_PI);
}

double EvansFungShape::area() const {
  // A = 2 * int 2 pi r sqrt(dr^2 + dz^2) along the meridian, parametrised by t (rho = sin t).
  auto meridian = [&](double t) {
    const double s = std::sin(t), c = std::cos(t);
    const double p = c0 + c2 * s * s + c4 * s * s * s * s;
    const double dp = (2.0 * c2 * s + 4.0 * c4 * s * s * s) * c;
    // r = R s, z = (R/2) c p(s)
    const double dr = radius * c;
    const double dz = 0.5 * radius * (-s * p + c * dp);
    return 4.0 * M_PI * radius * s * std::sqrt(dr * dr + dz * dz);
  };
  return simpson(meridian, 0.0, 0.5 * M_PI);
}

double EvansFungShape::max_thickness() const {
  double best = 0.0;
  for (int i = 0; i <= 100000; ++i)
    best = std::max(best, 2.0 * half_thickness(radius * i / 100000.0));
  return best;
}

}  // namespace dld::membrane
