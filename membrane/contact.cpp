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
  if (s >= rc) {
    return 0.0;
  }
  const double smin = kMinFraction * rc;
  if (s < smin) {
    const double e = eps * (rc - smin) * (rc - smin) / (smin * rc);
    return e + force(smin) * (smin - s);
  }
  return eps * (rc - s) * (rc - s) / (s * rc);
}

double ContactLaw::force(double s) const {
  if (s >= rc) {
    return 0.0;
  }
  s = std::max(s, kMinFraction * rc);
  return eps * (rc * rc - s * s) / (rc * s * s);
}

Contact::Contact(const DldCell& box_lu, const ContactParams& p)
    : box_(box_lu), p_(p), law_{p.range, p.strength}, skin_(0.3 * p.range) {
  if (!(p.range > 0.0) || !std::isfinite(p.range)) {
    throw InputError(fmt::format("contact: range must be positive, got {}", p.range));
  }
  if (!(p.strength >= 0.0) || !std::isfinite(p.strength)) {
    throw InputError(fmt::format("contact: strength must be >= 0, got {}", p.strength));
  }
  if (p.range > 0.25 * std::min(box_lu.lambda, box_lu.depth * 2.0)) {
    throw InputError(fmt::format("contact: range {} is too large for the box (lambda {}, depth {})",
                                 p.range, box_lu.lambda, box_lu.depth));
  }
}

void Contact::wrap_nodes(const Points& x) const {
  const int n = static_cast<int>(x.cols());
  wrapped_.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const Wrapped w = wrap_into_box(box_, {x(0, i), x(1, i), x(2, i)});
    wrapped_[static_cast<std::size_t>(i)] = {w.position[0], w.position[1], w.position[2]};
  }
}

void Contact::build_images(int nodes_per_cell, double cutoff) const {
  const int n = static_cast<int>(wrapped_.size());
  const double L = box_.lambda, rc = cutoff;
  image_pos_.clear();
  image_node_.clear();
  image_pos_.reserve(2 * static_cast<std::size_t>(n));
  image_node_.reserve(2 * static_cast<std::size_t>(n));
  double zmin = 1e300, zmax = -1e300;
  auto add_y = [&](Eigen::Vector3d q, int i) {
    image_pos_.push_back(q);
    image_node_.push_back(i);
    if (q.y() < rc) {
      image_pos_.push_back(q + Eigen::Vector3d(0, L, 0)), image_node_.push_back(i);
    }
    if (q.y() >= L - rc) {
      image_pos_.push_back(q - Eigen::Vector3d(0, L, 0)), image_node_.push_back(i);
    }
  };
  auto fold_y = [&](Eigen::Vector3d q) {
    q.y() -= L * std::floor(q.y() / L);
    if (q.y() >= L) {
      q.y() -= L;
    }
    return q;
  };
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& q = wrapped_[static_cast<std::size_t>(i)];
    zmin = std::min(zmin, q.z());
    zmax = std::max(zmax, q.z());
    add_y(q, i);
    // Shifted periodic x: (e, y) near x = 0 is the same point as (lambda + e, y + d).
    if (q.x() < rc) {
      add_y(fold_y(q + Eigen::Vector3d(L, box_.shift, 0)), i);
    }
    if (q.x() >= L - rc) {
      add_y(fold_y(q - Eigen::Vector3d(L, box_.shift, 0)), i);
    }
  }
  // Bins of side >= cutoff over [-cutoff, L + cutoff)^2 x [zmin, zmax].
  nbx_ = std::max(1, static_cast<int>(std::floor((L + 2 * rc) / rc)));
  bin_ = (L + 2 * rc) / nbx_;
  nby_ = nbx_;
  z0_ = zmin;
  nbz_ = std::max(1, static_cast<int>(std::floor((zmax - zmin) / bin_)) + 1);
  const int nb = nbx_ * nby_ * nbz_;
  bin_start_.assign(static_cast<std::size_t>(nb) + 1, 0);
  const int m = static_cast<int>(image_pos_.size());
  std::vector<int> bin_of(static_cast<std::size_t>(m));
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector3d& q = image_pos_[static_cast<std::size_t>(k)];
    const int bx = std::clamp(static_cast<int>((q.x() + rc) / bin_), 0, nbx_ - 1);
    const int by = std::clamp(static_cast<int>((q.y() + rc) / bin_), 0, nby_ - 1);
    const int bz = std::clamp(static_cast<int>((q.z() - z0_) / bin_), 0, nbz_ - 1);
    bin_of[static_cast<std::size_t>(k)] = (bz * nby_ + by) * nbx_ + bx;
    bin_start_[static_cast<std::size_t>(bin_of[static_cast<std::size_t>(k)]) + 1]++;
  }
  for (int b = 0; b < nb; ++b) {
    bin_start_[b + 1] += bin_start_[b];
  }
  sorted_.resize(static_cast<std::size_t>(m));
  std::vector<int> fill(bin_start_.begin(), bin_start_.end() - 1);
  for (int k = 0; k < m; ++k) {
    const auto kk = static_cast<std::size_t>(k);
    const Eigen::Vector3d& q = image_pos_[kk];
    const int node = image_node_[kk];
    sorted_[static_cast<std::size_t>(fill[static_cast<std::size_t>(bin_of[kk])]++)] = {
        q.x(), q.y(), q.z(), cell_of_[static_cast<std::size_t>(node / nodes_per_cell)], node};
  }
}

bool Contact::pairs_stale(const Points& x, int nodes_per_cell) const {
  if (x.cols() != x_built_.cols() || nodes_per_cell != built_nodes_per_cell_ ||
      cell_of_ != cells_built_) {
    return true;
  }
  const double limit = 0.25 * skin_ * skin_;  // (skin / 2)^2
  return ((x - x_built_).colwise().squaredNorm().array() > limit).any();
}

void Contact::build_pairs(const Points& x, int nodes_per_cell, int own_nodes) const {
  const double cut = p_.range + skin_, cut2 = cut * cut;
  build_images(nodes_per_cell, cut);
  const int n = own_nodes;  // ghost nodes get no list: their forces are their process's
  // Pairs in global node order: the same order whatever the split over processes.
  const auto global = [&](int node) {
    return static_cast<long>(cell_of_[static_cast<std::size_t>(node / nodes_per_cell)]) *
               nodes_per_cell +
           node % nodes_per_cell;
  };
  std::vector<std::vector<Neighbour>> lists(static_cast<std::size_t>(n));
#pragma omp parallel for schedule(static) if (n > 1024)
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& q = wrapped_[static_cast<std::size_t>(i)];
    const int cell = cell_of_[static_cast<std::size_t>(i / nodes_per_cell)];
    const int bx = std::clamp(static_cast<int>((q.x() + cut) / bin_), 0, nbx_ - 1);
    const int by = std::clamp(static_cast<int>((q.y() + cut) / bin_), 0, nby_ - 1);
    const int bz = std::clamp(static_cast<int>((q.z() - z0_) / bin_), 0, nbz_ - 1);
    const int x_lo = std::max(0, bx - 1), x_hi = std::min(nbx_ - 1, bx + 1);
    auto& list = lists[static_cast<std::size_t>(i)];
    for (int z = std::max(0, bz - 1); z <= std::min(nbz_ - 1, bz + 1); ++z) {
      for (int y = std::max(0, by - 1); y <= std::min(nby_ - 1, by + 1); ++y) {
        const auto row = (static_cast<std::size_t>(z) * nby_ + y) * nbx_;
        for (int s = bin_start_[row + static_cast<std::size_t>(x_lo)];
             s < bin_start_[row + static_cast<std::size_t>(x_hi) + 1]; ++s) {
          const Image& im = sorted_[static_cast<std::size_t>(s)];
          if (im.cell == cell) {
            continue;
          }
          const Eigen::Vector3d d(q.x() - im.x, q.y() - im.y, q.z() - im.z);
          if (d.squaredNorm() >= cut2) {
            continue;
          }
          // The periodic translation between the unwrapped nodes, fixed until the next build:
          // kx (lambda, d, 0) + ky (0, lambda, 0), rounded to those whole numbers so that it is
          // exact (and the same from any build).
          const Eigen::Vector3d t = x.col(i) - x.col(im.node) - d;
          const double kx = std::round(t.x() / box_.lambda);
          const double ky = std::round((t.y() - kx * box_.shift) / box_.lambda);
          list.push_back({im.node, Eigen::Vector3d(kx * box_.lambda,
                                                   kx * box_.shift + ky * box_.lambda, 0.0)});
        }
      }
    }
    // A canonical order (by node, then translation): the sum over a node's pairs is then the same
    // whichever step built the list.
    std::sort(list.begin(), list.end(), [&](const Neighbour& a, const Neighbour& b) {
      if (a.node != b.node) {
        return global(a.node) < global(b.node);
      }
      return std::lexicographical_compare(a.shift.data(), a.shift.data() + 3, b.shift.data(),
                                          b.shift.data() + 3);
    });
  }
  pair_start_.assign(static_cast<std::size_t>(n) + 1, 0);
  for (int i = 0; i < n; ++i) {
    pair_start_[static_cast<std::size_t>(i) + 1] =
        pair_start_[static_cast<std::size_t>(i)] +
        static_cast<int>(lists[static_cast<std::size_t>(i)].size());
  }
  pairs_list_.clear();
  pairs_list_.reserve(static_cast<std::size_t>(pair_start_.back()));
  for (auto& l : lists) {
    pairs_list_.insert(pairs_list_.end(), l.begin(), l.end());
  }
  x_built_ = x;
  built_nodes_per_cell_ = nodes_per_cell;
  cells_built_ = cell_of_;
}

const Points& Contact::gather(const Points& x, int nodes_per_cell,
                              const ContactGhosts* ghosts) const {
  const int own_cells = static_cast<int>(x.cols()) / nodes_per_cell;
  const int first = ghosts ? ghosts->first_cell : 0;
  cell_of_.resize(static_cast<std::size_t>(own_cells));
  for (int k = 0; k < own_cells; ++k) cell_of_[static_cast<std::size_t>(k)] = first + k;
  if (!ghosts || ghosts->cells.empty()) return x;
  if (ghosts->x.cols() != Eigen::Index{nodes_per_cell} * std::ssize(ghosts->cells)) {
    throw InputError(fmt::format("contact: {} ghost cells of {} nodes, {} ghost nodes given",
                                 ghosts->cells.size(), nodes_per_cell, ghosts->x.cols()));
  }
  cell_of_.insert(cell_of_.end(), ghosts->cells.begin(), ghosts->cells.end());
  with_ghosts_.resize(3, x.cols() + ghosts->x.cols());
  with_ghosts_.leftCols(x.cols()) = x;
  with_ghosts_.rightCols(ghosts->x.cols()) = ghosts->x;
  return with_ghosts_;
}

double Contact::evaluate(const Points& own, int nodes_per_cell, Points* f,
                         const ContactGhosts* ghosts) const {
  const int n = static_cast<int>(own.cols());
  const Points& x = gather(own, nodes_per_cell, ghosts);  // own nodes first, then the ghosts'
  const double rc = p_.range, rc2 = rc * rc;
  const bool pairs = p_.cells && x.cols() > nodes_per_cell;
  wrap_nodes(x);
  if (pairs && pairs_stale(x, nodes_per_cell)) {
    build_pairs(x, nodes_per_cell, n);
  }
  double energy = 0.0;
  long pair_count = 0, ghost_count = 0;
#pragma omp parallel for reduction(+ : energy, pair_count, ghost_count) schedule(static) \
    if (n > 1024)
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& q = wrapped_[i];
    Eigen::Vector3d fi = Eigen::Vector3d::Zero();
    if (p_.walls) {
      energy += law_.energy(q.z()) + law_.energy(box_.depth - q.z());
      fi.z() += law_.force(q.z()) - law_.force(box_.depth - q.z());
    }
    if (p_.pillar && box_.pillar_within(q.x(), q.y(), rc)) {
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
      for (int p = pair_start_[static_cast<std::size_t>(i)];
           p < pair_start_[static_cast<std::size_t>(i) + 1]; ++p) {
        const Neighbour& nb = pairs_list_[static_cast<std::size_t>(p)];
        const Eigen::Vector3d d = x.col(i) - x.col(nb.node) - nb.shift;
        const double r2 = d.squaredNorm();
        if (r2 >= rc2) {
          continue;
        }
        const double r = std::sqrt(r2);
        energy += 0.5 * law_.energy(r);  // each pair is seen from both sides
        if (nb.node < n) {
          ++pair_count;
        } else {
          ++ghost_count;  // seen here from one side only
        }
        fi += law_.force(r) * d / std::max(r, 1e-12 * rc);
      }
    }
    if (f) {
      f->col(i) += fi;
    }
  }
  pairs_ = pair_count / 2 + ghost_count;
  ghost_pairs_ = ghost_count;
  return energy;
}

double Contact::add_forces(const Points& x, int nodes_per_cell, Points& f,
                           const ContactGhosts* ghosts) const {
  return evaluate(x, nodes_per_cell, &f, ghosts);
}

double Contact::energy(const Points& x, int nodes_per_cell, const ContactGhosts* ghosts) const {
  return evaluate(x, nodes_per_cell, nullptr, ghosts);
}

}  // namespace dld::membrane
