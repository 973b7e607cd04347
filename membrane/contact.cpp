// SPDX-License-Identifier: MIT
#include "membrane/contact.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {
constexpr double kMinFraction = 0.05;  // s_min / r_c
}

double ContactLaw::energy(double s) const {
  if (s >= rc) return 0.0;
  const double smin = kMinFraction * rc;
  if (s < smin) {
    const double e = eps * (rc - smin) * (rc - smin) / (smin * rc);
    return e + force(smin) * (smin - s);
  }
  return eps * (rc - s) * (rc - s) / (s * rc);
}

double ContactLaw::force(double s) const {
  if (s >= rc) return 0.0;
  s = std::max(s, kMinFraction * rc);
  return eps * (rc * rc - s * s) / (rc * s * s);
}

Contact::Contact(const DldCell& box_lu, const ContactParams& p)
    : box_(box_lu), p_(p), law_{p.range, p.strength} {
  if (!(p.range > 0.0) || !std::isfinite(p.range))
    throw InputError(fmt::format("contact: range must be positive, got {}", p.range));
  if (!(p.strength >= 0.0) || !std::isfinite(p.strength))
    throw InputError(fmt::format("contact: strength must be >= 0, got {}", p.strength));
  if (p.range > 0.25 * std::min(box_lu.lambda, box_lu.depth * 2.0))
    throw InputError(fmt::format("contact: range {} is too large for the box (lambda {}, depth {})",
                                 p.range, box_lu.lambda, box_lu.depth));
}

void Contact::build_images(const Points& x, int nodes_per_cell) const {
  const int n = static_cast<int>(x.cols());
  const double L = box_.lambda, rc = p_.range;
  wrapped_.resize(n);
  image_pos_.clear();
  image_node_.clear();
  image_pos_.reserve(2 * n);
  image_node_.reserve(2 * n);
  double zmin = 1e300, zmax = -1e300;
  auto add_y = [&](Eigen::Vector3d q, int i) {
    image_pos_.push_back(q);
    image_node_.push_back(i);
    if (q.y() < rc) image_pos_.push_back(q + Eigen::Vector3d(0, L, 0)), image_node_.push_back(i);
    if (q.y() >= L - rc)
      image_pos_.push_back(q - Eigen::Vector3d(0, L, 0)), image_node_.push_back(i);
  };
  auto fold_y = [&](Eigen::Vector3d q) {
    q.y() -= L * std::floor(q.y() / L);
    if (q.y() >= L) q.y() -= L;
    return q;
  };
  for (int i = 0; i < n; ++i) {
    const Wrapped w = wrap_into_box(box_, {x(0, i), x(1, i), x(2, i)});
    const Eigen::Vector3d q(w.position[0], w.position[1], w.position[2]);
    wrapped_[i] = q;
    zmin = std::min(zmin, q.z());
    zmax = std::max(zmax, q.z());
    add_y(q, i);
    // Shifted periodic x: (e, y) near x = 0 is the same point as (lambda + e, y + d).
    if (q.x() < rc) add_y(fold_y(q + Eigen::Vector3d(L, box_.shift, 0)), i);
    if (q.x() >= L - rc) add_y(fold_y(q - Eigen::Vector3d(L, box_.shift, 0)), i);
  }
  // Bins of side >= r_c over [-r_c, L + r_c)^2 x [zmin, zmax].
  nbx_ = std::max(1, static_cast<int>(std::floor((L + 2 * rc) / rc)));
  bin_ = (L + 2 * rc) / nbx_;
  nby_ = nbx_;
  z0_ = zmin;
  nbz_ = std::max(1, static_cast<int>(std::floor((zmax - zmin) / bin_)) + 1);
  const int nb = nbx_ * nby_ * nbz_;
  bin_start_.assign(nb + 1, 0);
  const int m = static_cast<int>(image_pos_.size());
  std::vector<int> bin_of(m);
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d& q = image_pos_[k];
    const int bx = std::clamp(static_cast<int>((q.x() + rc) / bin_), 0, nbx_ - 1);
    const int by = std::clamp(static_cast<int>((q.y() + rc) / bin_), 0, nby_ - 1);
    const int bz = std::clamp(static_cast<int>((q.z() - z0_) / bin_), 0, nbz_ - 1);
    bin_of[k] = (bz * nby_ + by) * nbx_ + bx;
    bin_start_[bin_of[k] + 1]++;
  }
  for (int b = 0; b < nb; ++b) bin_start_[b + 1] += bin_start_[b];
  sorted_.resize(m);
  std::vector<int> fill(bin_start_.begin(), bin_start_.end() - 1);
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d& q = image_pos_[k];
    sorted_[fill[bin_of[k]]++] = {q.x(), q.y(), q.z(), image_node_[k] / nodes_per_cell};
  }
}

double Contact::evaluate(const Points& x, int nodes_per_cell, Points* f) const {
  const int n = static_cast<int>(x.cols());
  const double rc = p_.range, rc2 = rc * rc;
  const bool pairs = p_.cells && n > nodes_per_cell;
  if (pairs || p_.walls || p_.pillar) build_images(x, nodes_per_cell);
  double energy = 0.0;
  long pair_count = 0;
#pragma omp parallel for reduction(+ : energy, pair_count) schedule(static) if (n > 1024)
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& q = wrapped_[i];
    Eigen::Vector3d fi = Eigen::Vector3d::Zero();
    if (p_.walls) {
      energy += law_.energy(q.z()) + law_.energy(box_.depth - q.z());
      fi.z() += law_.force(q.z()) - law_.force(box_.depth - q.z());
    }
    if (p_.pillar) {
      const double s = box_.pillar_distance(q.x(), q.y());
      if (s < rc) {
        energy += law_.energy(s);
        // Outward normal of the distance field by central differences (cheap, exact enough: the
        // field is a circle distance, smooth away from the pillar centre).
        const double h = 1e-6 * box_.lambda;
        Eigen::Vector3d g(
            (box_.pillar_distance(q.x() + h, q.y()) - box_.pillar_distance(q.x() - h, q.y())) /
                (2 * h),
            (box_.pillar_distance(q.x(), q.y() + h) - box_.pillar_distance(q.x(), q.y() - h)) /
                (2 * h),
            0.0);
        fi += law_.force(s) * g;
      }
    }
    if (pairs) {
      const int cell = i / nodes_per_cell;
      const int bx = std::clamp(static_cast<int>((q.x() + rc) / bin_), 0, nbx_ - 1);
      const int by = std::clamp(static_cast<int>((q.y() + rc) / bin_), 0, nby_ - 1);
      const int bz = std::clamp(static_cast<int>((q.z() - z0_) / bin_), 0, nbz_ - 1);
      const int x_lo = std::max(0, bx - 1), x_hi = std::min(nbx_ - 1, bx + 1);
      for (int z = std::max(0, bz - 1); z <= std::min(nbz_ - 1, bz + 1); ++z)
        for (int y = std::max(0, by - 1); y <= std::min(nby_ - 1, by + 1); ++y) {
          const int row = (z * nby_ + y) * nbx_;
          for (int s = bin_start_[row + x_lo]; s < bin_start_[row + x_hi + 1]; ++s) {
            const Image& im = sorted_[s];
            if (im.cell == cell) continue;
            const Eigen::Vector3d d(q.x() - im.x, q.y() - im.y, q.z() - im.z);
            const double r2 = d.squaredNorm();
            if (r2 >= rc2) continue;
            const double r = std::sqrt(r2);
            energy += 0.5 * law_.energy(r);  // each pair is seen from both sides
            ++pair_count;
            fi += law_.force(r) * d / std::max(r, 1e-12 * rc);
          }
        }
    }
    if (f) f->col(i) += fi;
  }
  pairs_ = pair_count / 2;
  return energy;
}

double Contact::add_forces(const Points& x, int nodes_per_cell, Points& f) const {
  return evaluate(x, nodes_per_cell, &f);
}

double Contact::energy(const Points& x, int nodes_per_cell) const {
  return evaluate(x, nodes_per_cell, nullptr);
}

}  // namespace dld::membrane
