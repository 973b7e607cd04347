// SPDX-License-Identifier: MIT
#include "membrane/packing.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <ctime>
#include <random>

#include "membrane/cell_set.hpp"
#include "membrane/lbfgs.hpp"
#include "shared/input_error.hpp"

namespace dld::membrane {
namespace {

// Packing mechanics, in units of kappa_s = 1. Fixed (not the scene's moduli) so that every run
// at the same haematocrit starts from the same state whatever its capillary number.
constexpr double kAreaRatio = 10.0;     // kappa_alpha / kappa_s: local area nearly kept
constexpr double kBendingRel = 2.5e-3;  // kappa_b / (kappa_s r^2), SPEC section 4
constexpr double kVolumeRel = 1000.0;   // kappa_V r / kappa_s: volume kept to ~0.1 %
// Contact while packing: range and target gap relative to the required clearance, so that the
// final gaps end above the clearance with a margin; strength relative to kappa_s range^2.
constexpr double kRangeFactor = 1.6;
constexpr double kTargetFactor = 1.2;
constexpr double kStrengthRel = 2.0;
constexpr int kChunk = 40;        // L-BFGS iterations between gap checks
constexpr int kSettleChunks = 5;  // extra chunks at full size so shapes settle

/// Uniform in [0, 1) from the top 53 bits (the same sequence with every standard library).
double uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

MembraneMechanics packing_mechanics(const TriMesh& ref, double radius) {
  std::vector<AnyModel> m;
  m.emplace_back(SkalakModel(ref, {1.0, kAreaRatio}));
  m.emplace_back(BendingModel(ref, {kBendingRel * radius * radius}));
  m.emplace_back(VolumePenalty(ref, {kVolumeRel / radius}));
  return MembraneMechanics({"skalak", "bending", "volume"}, std::move(m));
}

/// Random sequential addition of cells shrunk to `scale`: each cell's disk (in-plane radius plus
/// the contact range) must clear the pillar and the other disks, across the periodic faces.
Points place_shrunk(const TriMesh& ref, const DldCell& box, const PackOptions& o, double scale,
                    double range) {
  const double r = scale * ref.nodes.topRows<2>().colwise().norm().maxCoeff();
  const double half = scale * ref.nodes.row(2).cwiseAbs().maxCoeff();
  if (2 * (half + range) > box.depth)
    throw InputError(
        fmt::format("packing: a cell {:.3g} thick does not fit the depth {:.3g} with "
                    "gaps {:.3g} (lattice lengths)",
                    2 * half, box.depth, range));
  std::mt19937_64 rng(o.seed);
  std::vector<Eigen::Vector2d> centres;
  Points x(3, 0);
  for (int k = 0; k < o.count; ++k) {
    bool placed = false;
    for (int attempt = 0; attempt < 100000 && !placed; ++attempt) {
      const Eigen::Vector2d c(box.lambda * uniform(rng), box.lambda * uniform(rng));
      const double angle = 2 * M_PI * uniform(rng);
      if (box.pillar_distance(c.x(), c.y()) < r + range) continue;
      placed = true;
      for (const auto& q : centres)
        for (int ix = -1; ix <= 1 && placed; ++ix)
          for (int iy = -2; iy <= 2 && placed; ++iy) {
            const Eigen::Vector2d t(ix * box.lambda, ix * box.shift + iy * box.lambda);
            if ((c - q - t).norm() < 2 * r + range) placed = false;
          }
      if (!placed) continue;
      centres.push_back(c);
      const Eigen::Matrix3d rot =
          Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      const Points cell =
          ((scale * rot) * ref.nodes).colwise() + Eigen::Vector3d(c.x(), c.y(), 0.5 * box.depth);
      x.conservativeResize(3, x.cols() + cell.cols());
      x.rightCols(cell.cols()) = cell;
    }
    if (!placed)
      throw InputError(fmt::format("packing: no room for cell {} of {} even at {} of full size",
                                   k + 1, o.count, scale));
  }
  return x;
}

/// Minimises membrane + contact energy in chunks until every gap reaches `target` (and, when
/// `settle`, a few chunks more). Returns the iterations used.
int relax(CellSet& cells, const DldCell& box, double target, double range, bool settle, int budget,
          Clearances& gaps) {
  const int n = cells.nodes_per_cell();
  Eigen::VectorXd v =
      Eigen::Map<const Eigen::VectorXd>(cells.positions().data(), cells.positions().size());
  const Objective energy = [&](const Eigen::VectorXd& y, Eigen::VectorXd& grad) {
    cells.positions() = Eigen::Map<const Points>(y.data(), 3, cells.node_count());
    Points f;
    const double e = cells.compute_forces(f);
    grad = -Eigen::Map<const Eigen::VectorXd>(f.data(), f.size());
    return e;
  };
  LbfgsOptions lo;
  lo.max_iterations = kChunk;
  lo.gradient_tolerance = 1e-6;
  lo.max_step = 0.1 * range;  // a node moves a fraction of the contact range per iteration
  int used = 0, settled = 0;
  while (used < budget) {
    const LbfgsResult r = minimize_lbfgs(v, energy, lo);
    used += std::max(1, r.iterations);
    cells.positions() = Eigen::Map<const Points>(v.data(), 3, cells.node_count());
    gaps = clearances(cells.positions(), n, box, range);
    if (gaps.min() >= target && (!settle || ++settled >= kSettleChunks || r.converged)) break;
  }
  return used;
}

}  // namespace

double largest_tilt_deg(const Points& x, int n) {
  double tilt = 0.0;
  for (int k = 0; Eigen::Index{k} * n < x.cols(); ++k) {
    const Points d = x.middleCols(Eigen::Index{k} * n, n).colwise() -
                     x.middleCols(Eigen::Index{k} * n, n).rowwise().mean();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(d * d.transpose());
    const double c = std::abs(eig.eigenvectors().col(0).z());  // eigenvalues ascending
    tilt = std::max(tilt, std::acos(std::min(1.0, c)) * 180.0 / M_PI);
  }
  return tilt;
}

PackedCells pack_cells(const TriMesh& reference, const DldCell& box, const PackOptions& o,
                       const PackLog& log) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  if (o.count < 1) throw InputError(fmt::format("packing: cell count {} must be >= 1", o.count));
  TriMesh ref = reference;
  ref.nodes.colwise() -= centroid(ref.nodes);
  const double radius = ref.nodes.topRows<2>().colwise().norm().maxCoeff();
  const double range = kRangeFactor * o.clearance, target = kTargetFactor * o.clearance;
  const int n = ref.node_count();

  PackedCells out;
  out.nodes_per_cell = n;
  // Crowded boxes (many cells, wide contact range): place smaller still, down to a fifth.
  double scale = o.start_scale;
  Points x;
  for (;;) {
    try {
      x = place_shrunk(ref, box, o, scale, range);
      break;
    } catch (const InputError&) {
      if (scale * 0.8 < 0.2) throw;
      scale *= 0.8;
    }
  }
  const Contact contact(box, {range, kStrengthRel * range * range, true, true, true});
  PackReport& rep = out.report;
  for (;;) {
    TriMesh ref_s = ref;
    ref_s.nodes *= scale;
    CellSet cells(ref_s, packing_mechanics(ref_s, scale * radius), contact);
    for (int k = 0; k < o.count; ++k) cells.add_cell(Points(x.middleCols(Eigen::Index{k} * n, n)));
    const bool full = scale >= 1.0;
    Clearances gaps;
    rep.iterations +=
        relax(cells, box, target, range, full, o.max_iterations - rep.iterations, gaps);
    x = cells.positions();
    ++rep.stages;
    if (log)
      log(fmt::format(
          "stage {:3d}: size {:.3f}, {:6d} iterations, gaps cells {:.3f}, walls "
          "{:.3f}, pillar {:.3f} (lattice lengths; target {:.3f})",
          rep.stages, scale, rep.iterations, gaps.cells, gaps.walls, gaps.pillar, target));
    if (rep.iterations >= o.max_iterations) {
      if (full && gaps.min() > o.clearance) break;  // clear, though short of the margin
      throw InputError(fmt::format(
          "packing {} cells: gaps still below {:.3g} after {} iterations (size {:.3f}, smallest "
          "gap {:.3g} lattice lengths): fewer cells or a shorter contact range",
          o.count, target, rep.iterations, scale, gaps.min()));
    }
    if (full) break;
    // Grow every cell about its centroid (deformed shapes included).
    const double next = std::min(1.0, scale + o.scale_step);
    for (int k = 0; k < o.count; ++k) {
      auto xk = x.middleCols(Eigen::Index{k} * n, n);
      const Eigen::Vector3d c = xk.rowwise().mean();
      xk = ((xk.colwise() - c) * (next / scale)).colwise() + c;
    }
    scale = next;
  }
  fold_cells_into_box(x, n, box);
  out.positions = x;
  rep.gaps = clearances(x, n, box, box.lambda);
  if (!(rep.gaps.min() > o.clearance))
    throw InputError(
        fmt::format("packing {} cells: smallest gap {:.3g} is not above the contact "
                    "range {:.3g} (lattice lengths)",
                    o.count, rep.gaps.min(), o.clearance));
  if (const int inside = nodes_inside_other_cells(x, ref.faces, n, box))
    throw InputError(
        fmt::format("packing {} cells: {} nodes lie inside other cells", o.count, inside));
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  rep.cpu_seconds = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return out;
}

}  // namespace dld::membrane
