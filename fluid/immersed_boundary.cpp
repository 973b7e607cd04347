// SPDX-License-Identifier: MIT
#include "fluid/immersed_boundary.hpp"

#include <omp.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "fluid/ib_axis_batch.hpp"
#include "shared/input_error.hpp"

namespace dld::fluid {

IbKernel ib_kernel_from_name(const std::string& name) {
  if (name == "peskin2") return IbKernel::kPeskin2;
  if (name == "peskin3") return IbKernel::kPeskin3;
  if (name == "peskin4") return IbKernel::kPeskin4;
  throw InputError("immersed-boundary kernel '" + name + "': expected peskin2, peskin3 or peskin4");
}

ImmersedBoundary::ImmersedBoundary(const Lattice& lattice, IbKernel kernel)
    : lattice_(lattice),
      kernel_(kernel),
      column_solid_(static_cast<std::size_t>(lattice.px()) * lattice.py(), 0),
      column_all_solid_(column_solid_.size(), 1) {
  const std::size_t plane = column_solid_.size();
  const std::uint8_t* solid = lattice.solid_mask().data();
  for (int k = 0; k < lattice.nz(); ++k) {
    const std::uint8_t* layer = solid + lattice.index(-1, -1, k);
    for (std::size_t c = 0; c < plane; ++c) {
      column_solid_[c] |= layer[c];
      column_all_solid_[c] &= layer[c];
    }
  }
  const int nx = lattice.nx(), ny = lattice.ny(), w = static_cast<int>(kernel);
  const auto px = static_cast<std::size_t>(lattice.px());
  block_solid_.assign(static_cast<std::size_t>(nx) * ny, 1);
  for (int j0 = 0; j0 < ny; ++j0)
    for (int i0 = 0; i0 + w <= nx; ++i0) {
      std::uint8_t any = 0;
      for (int b = 0; b < w; ++b) {
        const auto row = static_cast<std::size_t>((j0 + b) % ny + 1) * px;
        for (int a = 0; a < w; ++a)
          any |= column_solid_[row + static_cast<std::size_t>(i0 + a + 1)];
      }
      block_solid_[static_cast<std::size_t>(j0) * nx + i0] = any;
    }
}

namespace {
[[noreturn]] void no_fluid_near(std::size_t marker, const double* p) {
  throw std::runtime_error("immersed boundary: marker " + std::to_string(marker) + " at (" +
                           std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                           std::to_string(p[2]) +
                           ") has no fluid node within its kernel (inside a pillar or a wall?)");
}

/// Where a marker's support starts after folding x into the box: its first x column (may be < 0
/// or > nx - W: the support then crosses the shifted x face; INT_MIN if not finite), and as the
/// return value its (x, y) column bin j * nx + i, for sorting markers so that neighbours in
/// memory are neighbours in the lattice (nx * ny if not finite).
std::size_t locate(const double* p, const Domain& d, int width, int& first) {
  first = std::numeric_limits<int>::min();
  if (!std::isfinite(p[0])) return static_cast<std::size_t>(d.nx) * d.ny;
  const double wraps = std::floor(p[0] / d.nx);
  const double X = p[0] - wraps * d.nx, Y = p[1] - wraps * d.shift;
  first = static_cast<int>(std::floor(X - 0.5 - 0.5 * width)) + 1;
  if (!std::isfinite(p[1])) return static_cast<std::size_t>(d.nx) * d.ny;
  const int i = std::clamp(first, 0, d.nx - 1);
  const double y = Y - std::floor(Y / d.ny) * d.ny;
  const int j = std::clamp(static_cast<int>(y), 0, d.ny - 1);
  return static_cast<std::size_t>(j) * d.nx + i;
}
}  // namespace

void ImmersedBoundary::locate_markers(std::span<const double> positions, int width) const {
  const Domain& d = lattice_.domain();
  const auto markers = static_cast<std::int64_t>(positions.size() / 3);
  first_.resize(static_cast<std::size_t>(markers));
  bin_.resize(static_cast<std::size_t>(markers));
#pragma omp parallel for schedule(static)
  for (std::int64_t m = 0; m < markers; ++m) {
    const double* p = &positions[3 * static_cast<std::size_t>(m)];
    const auto k = static_cast<std::size_t>(m);
    bin_[k] = static_cast<std::uint32_t>(locate(p, d, width, first_[k]));
  }
}

// Counting sort of the markers by bin_ (locate_markers first) into by_column_.
void ImmersedBoundary::sort_by_column() const {
  const Domain& d = lattice_.domain();
  const std::size_t bins = static_cast<std::size_t>(d.nx) * d.ny + 1;
  bin_start_.assign(bins + 1, 0);
  for (const std::uint32_t b : bin_) ++bin_start_[b + 1];
  for (std::size_t b = 1; b <= bins; ++b) bin_start_[b] += bin_start_[b - 1];
  by_column_.resize(bin_.size());
  for (std::size_t m = 0; m < bin_.size(); ++m)
    by_column_[bin_start_[bin_[m]]++] = static_cast<std::uint32_t>(m);
}

// Slab edges b_0 = 0 < b_1 < ... < b_T = nx at about equal marker counts, at least 2W apart, so
// that the markers inside different slabs, and those straddling different edges, never share a
// node: each group is spread by one thread into the one field, with no copies to add up.
// Uses first_ and by_column_ (locate_markers, sort_by_column).
void ImmersedBoundary::group_markers(int threads, int width) const {
  const int nx = lattice_.nx();
  const std::size_t markers = first_.size();
  std::vector<int> edge(static_cast<std::size_t>(threads) + 1, nx);
  edge[0] = 0;
  group_of_.resize(markers);
  if (threads > 1) {
    std::vector<std::size_t> below(static_cast<std::size_t>(nx) + 1, 0);
    for (const int i0 : first_) ++below[static_cast<std::size_t>(std::clamp(i0, 0, nx - 1)) + 1];
    for (int i = 0; i < nx; ++i)
      below[static_cast<std::size_t>(i) + 1] += below[static_cast<std::size_t>(i)];
    for (int t = 1; t < threads; ++t) {
      int b = 0;
      while (b < nx &&
             below[static_cast<std::size_t>(b)] * threads < markers * static_cast<std::size_t>(t))
        ++b;
      edge[static_cast<std::size_t>(t)] = std::clamp(
          b, edge[static_cast<std::size_t>(t) - 1] + 2 * width, nx - (threads - t) * 2 * width);
    }
  }
  std::vector<std::uint32_t> count(2 * static_cast<std::size_t>(threads) + 1, 0);
  for (std::size_t m = 0; m < markers; ++m) {
    const int i0 = first_[m];
    int g = threads;  // straddles x = 0 (or is not finite): the edge of slab 0
    if (i0 >= 0 && i0 + width <= nx) {
      int t = 0;
      while (edge[static_cast<std::size_t>(t) + 1] <= i0) ++t;
      g = i0 + width <= edge[static_cast<std::size_t>(t) + 1] ? t : threads + t + 1;
    }
    group_of_[m] = static_cast<std::uint8_t>(g);
    ++count[static_cast<std::size_t>(g) + 1];
  }
  for (std::size_t g = 1; g < count.size(); ++g) count[g] += count[g - 1];
  group_start_.assign(count.begin(), count.end());
  order_.resize(markers);
  // Within a group, markers in column order: their supports overlap in cache.
  for (const std::uint32_t m : by_column_) order_[count[group_of_[m]]++] = m;
}

// A marker without a separable footprint: across the shifted x face (split), else by the pillar
// (masked), else near a solid (stencil). Kept for the interpolation as its `q`-th marker (W = 4).
// False if no fluid is near.
template <int W>
bool ImmersedBoundary::spread_unseparable(std::uint32_t q, int thread, const double* p,
                                          const double* force, double* const out[3]) const {
  constexpr bool keep = W == 4;
  IbSplitFootprint<W> sp;
  if (split_footprint<W>(p, sp)) {
    if constexpr (keep) {
      spread_kind_[q] = kKeptSplit;
      spread_split_[q] = sp;
    }
    spread_footprint(sp, force, out);
    return true;
  }
  IbMaskedFootprint<W> mp;
  if (masked_footprint<W>(p, mp)) {
    if constexpr (keep) {
      keep_masked(mp, thread, spread_stencil_[q]);
      spread_kind_[q] = kKeptMasked;
    }
    spread_footprint(mp, force, out);
    return true;
  }
  IbStencil s;
  if (!std::isfinite(p[0]) || !stencil(p, s)) return false;
  const double f[3] = {force[0], force[1], force[2]};
  double* const o[3] = {out[0], out[1], out[2]};  // locals: no reload after each store
  for (int k = 0; k < s.count; ++k)
    for (int a = 0; a < 3; ++a) o[a][s.node[k]] += s.weight[k] * f[a];
  if constexpr (keep) {
    keep_stencil(s, thread, spread_stencil_[q]);
    spread_kind_[q] = kKeptStencil;
  }
  return true;
}

// spread_unseparable<4>()'s split and masked footprints from a batch's axis weights (the same
// bits); false for the others, which take spread_unseparable().
bool ImmersedBoundary::spread_batched_unseparable(const Peskin4AxisBatch& axes, int lane,
                                                  std::uint32_t q, int thread, const double* p,
                                                  const double* force, double* const out[3]) const {
  if (batched_split_footprint(axes, lane, p, spread_split_[q])) {
    spread_kind_[q] = kKeptSplit;
    spread_footprint(spread_split_[q], force, out);
    return true;
  }
  IbMaskedFootprint<4> mp;
  if (!batched_masked_footprint(axes, lane, p, mp)) return false;
  keep_masked(mp, thread, spread_stencil_[q]);
  spread_kind_[q] = kKeptMasked;
  spread_footprint(mp, force, out);
  return true;
}

template <int W>
void ImmersedBoundary::spread_w(std::span<const double> positions, std::span<const double> forces,
                                const std::array<double*, 3>& field) const {
  const std::size_t n = lattice_.padded_size();
  const std::size_t markers = positions.size() / 3;
  const int slabs = std::clamp(omp_get_max_threads(), 1, std::max(1, lattice_.nx() / (2 * W)));
  locate_markers(positions, W);
  sort_by_column();
  group_markers(slabs, W);
  // The default kernel (Peskin 4, the only one of width 4) keeps its footprints for
  // interpolation, and computes their axis weights SIMD across markers.
  constexpr bool keep = W == 4;
  assert(W != 4 || kernel_ == IbKernel::kPeskin4);
  const auto nx = static_cast<double>(lattice_.nx()), ny = static_cast<double>(lattice_.ny());
  const double shift = lattice_.domain().shift;
  if (keep) {
    spread_footprints_.resize(markers);
    spread_split_.resize(markers);
    spread_kind_.resize(markers);
    spread_stencil_.resize(markers);
    kept_nodes_.resize(static_cast<std::size_t>(slabs));
    kept_weights_.resize(static_cast<std::size_t>(slabs));
    kept_masked_.resize(static_cast<std::size_t>(slabs));
  }
  double* const out[3] = {field[0], field[1], field[2]};
  std::size_t bad = markers;
#pragma omp parallel num_threads(slabs) reduction(min : bad)
  {
    for (int a = 0; a < 3; ++a) {
#pragma omp for schedule(static) nowait
      for (std::size_t i = 0; i < n; ++i) field[a][i] = 0.0;
    }
    const int t = omp_get_thread_num(), nt = omp_get_num_threads();
    if constexpr (keep) {
      kept_nodes_[static_cast<std::size_t>(t)].clear();
      kept_weights_[static_cast<std::size_t>(t)].clear();
      kept_masked_[static_cast<std::size_t>(t)].clear();
    }
    IbFootprint<W> fp;
    Peskin4AxisBatch axes;
    bool batch_separable[kIbBatch] = {};
    // Phase 0: the markers inside each slab; phase 1: those straddling each slab's lower edge.
    for (int phase = 0; phase < 2; ++phase) {
#pragma omp barrier
      for (int g = phase * slabs + t; g < (phase + 1) * slabs; g += nt) {
        const std::uint32_t begin = group_start_[static_cast<std::size_t>(g)],
                            end = group_start_[static_cast<std::size_t>(g) + 1];
        for (std::uint32_t q = begin; q < end; ++q) {
          const std::size_t m = order_[q];
          bool separable = false;
          if constexpr (W == 4) {
            // A batch's footprints straight into the kept ones (the kernel is Peskin 4).
            const int lane = static_cast<int>((q - begin) % kIbBatch);
            if (lane == 0) {
              const int count = static_cast<int>(std::min<std::uint32_t>(kIbBatch, end - q));
              peskin4_axis_batch(positions.data(), &order_[q], count, nx, ny, shift, axes);
              batched_footprints(axes, count, positions.data(), &order_[q], &spread_footprints_[q],
                                 batch_separable);
            }
            separable = batch_separable[lane];
            spread_kind_[q] = separable ? kKeptSeparable : kKeptNone;
            if (separable) {
              spread_footprint(spread_footprints_[q], &forces[3 * m], out);
            } else {
              separable = spread_batched_unseparable(axes, lane, q, t, &positions[3 * m],
                                                     &forces[3 * m], out);
            }
          } else {
            separable = footprint<W>(&positions[3 * m], fp);
            if (separable) spread_footprint(fp, &forces[3 * m], out);
          }
          if (!separable && !spread_unseparable<W>(q, t, &positions[3 * m], &forces[3 * m], out))
            bad = std::min(bad, m);
        }
      }
    }
  }
  if (bad < markers) no_fluid_near(bad, &positions[3 * bad]);
  spread_positions_.assign(positions.begin(), positions.end());
  spread_done_ = true;
}

void ImmersedBoundary::spread(std::span<const double> positions, std::span<const double> forces,
                              const std::array<double*, 3>& field) const {
  assert(positions.size() == forces.size());
  switch (kernel_) {
    case IbKernel::kPeskin2:
      return spread_w<2>(positions, forces, field);
    case IbKernel::kPeskin3:
      return spread_w<3>(positions, forces, field);
    case IbKernel::kPeskin4:
      return spread_w<4>(positions, forces, field);
  }
}

void ImmersedBoundary::keep_stencil(const IbStencil& s, int thread, KeptStencil& kept) const {
  std::vector<std::size_t>& nodes = kept_nodes_[static_cast<std::size_t>(thread)];
  std::vector<double>& weights = kept_weights_[static_cast<std::size_t>(thread)];
  const auto count = static_cast<std::size_t>(s.count);
  kept = {static_cast<std::uint32_t>(thread), static_cast<std::uint32_t>(nodes.size()),
          static_cast<std::uint32_t>(count)};
  nodes.insert(nodes.end(), s.node.begin(), s.node.begin() + s.count);
  weights.insert(weights.end(), s.weight.begin(), s.weight.begin() + s.count);
}

void ImmersedBoundary::keep_masked(const IbMaskedFootprint<4>& fp, int thread,
                                   KeptStencil& kept) const {
  std::vector<IbMaskedFootprint<4>>& masked = kept_masked_[static_cast<std::size_t>(thread)];
  kept = {static_cast<std::uint32_t>(thread), static_cast<std::uint32_t>(masked.size()), 1};
  masked.push_back(fp);
}

// The same sum, in the same order, as interpolating through stencil() anew.
void ImmersedBoundary::interpolate_kept_stencil(const KeptStencil& kept, const double* const v[3],
                                                double* out) const {
  const std::size_t* node = kept_nodes_[kept.thread].data() + kept.offset;
  const double* weight = kept_weights_[kept.thread].data() + kept.offset;
  double u[3] = {0, 0, 0};
  for (std::uint32_t k = 0; k < kept.count; ++k)
    for (int a = 0; a < 3; ++a) u[a] += weight[k] * v[a][node[k]];
  for (int a = 0; a < 3; ++a) out[a] = u[a];
}

// A marker without a separable footprint (across the shifted x face, else by the pillar, else
// near a solid); false if no fluid is near.
template <int W>
bool ImmersedBoundary::interpolate_unseparable(const double* p, const double* const v[3],
                                               double* out) const {
  IbSplitFootprint<W> sp;
  if (split_footprint<W>(p, sp)) {
    interpolate_footprint(sp, v, out);
    return true;
  }
  IbMaskedFootprint<W> mp;
  if (masked_footprint<W>(p, mp)) {
    interpolate_footprint(mp, v, out);
    return true;
  }
  IbStencil s;
  if (!std::isfinite(p[0]) || !stencil(p, s)) return false;
  double u[3] = {0, 0, 0};
  for (int k = 0; k < s.count; ++k)
    for (int a = 0; a < 3; ++a) u[a] += s.weight[k] * v[a][s.node[k]];
  for (int a = 0; a < 3; ++a) out[a] = u[a];
  return true;
}

// Peskin 4 at positions other than the last spread's (held steps move the markers between
// spreads): the axis weights SIMD across batches of markers as spreading computes them (the
// footprints of footprint<4>(), bit for bit; the interpolation 1.6x cheaper on one thread, docs/
// performance.md, "Held steps interpolate with batched footprints"). The batches
// follow the last spread's order when it holds the same markers: they have moved a small part of
// a spacing since, so neighbours in memory are still neighbours in the lattice, and each marker's
// velocity does not depend on the order, so no new sort is needed.
void ImmersedBoundary::interpolate_moved(std::span<const double> positions,
                                         const double* const v[3], std::span<double> out) const {
  const std::size_t markers = positions.size() / 3;
  const bool reuse = spread_done_ && order_.size() == markers;
  if (!reuse) {
    locate_markers(positions, 4);
    sort_by_column();
  }
  const std::vector<std::uint32_t>& order = reuse ? order_ : by_column_;
  const auto nx = static_cast<double>(lattice_.nx()), ny = static_cast<double>(lattice_.ny());
  const double shift = lattice_.domain().shift;
  const auto batches = static_cast<std::int64_t>((markers + kIbBatch - 1) / kIbBatch);
  std::size_t bad = markers;  // first marker without fluid around it, if any
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (std::int64_t b = 0; b < batches; ++b) {
    const std::size_t first = static_cast<std::size_t>(b) * kIbBatch;
    const std::uint32_t* index = &order[first];
    const int count = static_cast<int>(std::min<std::size_t>(kIbBatch, markers - first));
    Peskin4AxisBatch axes;
    IbFootprint<4> fp[kIbBatch];
    bool separable[kIbBatch];
    peskin4_axis_batch(positions.data(), index, count, nx, ny, shift, axes);
    batched_footprints(axes, count, positions.data(), index, fp, separable);
    for (int lane = 0; lane < count; ++lane) {
      const std::size_t m = index[lane];
      IbMaskedFootprint<4> mp;
      IbSplitFootprint<4> sp;
      if (separable[lane]) {
        interpolate_footprint(fp[lane], v, &out[3 * m]);
      } else if (batched_masked_footprint(axes, lane, &positions[3 * m], mp)) {
        interpolate_footprint(mp, v, &out[3 * m]);
      } else if (batched_split_footprint(axes, lane, &positions[3 * m], sp)) {
        interpolate_footprint(sp, v, &out[3 * m]);
      } else if (!interpolate_unseparable<4>(&positions[3 * m], v, &out[3 * m])) {
        bad = std::min(bad, m);
      }
    }
  }
  if (bad < markers) no_fluid_near(bad, &positions[3 * bad]);
}

template <int W>
void ImmersedBoundary::interpolate_w(std::span<const double> positions,
                                     const std::array<const double*, 3>& velocity,
                                     std::span<double> out) const {
  const std::size_t markers = positions.size() / 3;
  const double* const v[3] = {velocity[0], velocity[1], velocity[2]};
  // At the positions of the last spread: its footprints, in its order (spatially sorted too).
  const bool kept = W == 4 && positions.size() == spread_positions_.size() &&
                    std::equal(positions.begin(), positions.end(), spread_positions_.begin());
  if (W == 4 && !kept) return interpolate_moved(positions, v, out);
  if (!kept) {
    locate_markers(positions, W);
    sort_by_column();
  }
  const std::vector<std::uint32_t>& order = kept ? order_ : by_column_;
  std::size_t bad = markers;  // first marker without fluid around it, if any
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (std::size_t q = 0; q < markers; ++q) {
    const std::size_t m = order[q];
    if constexpr (W == 4) {
      if (spread_kind_[q] == kKeptSeparable) {
        interpolate_footprint(spread_footprints_[q], v, &out[3 * m]);
        continue;
      }
      if (spread_kind_[q] == kKeptSplit) {
        interpolate_footprint(spread_split_[q], v, &out[3 * m]);
        continue;
      }
      if (spread_kind_[q] == kKeptStencil) {
        interpolate_kept_stencil(spread_stencil_[q], v, &out[3 * m]);
        continue;
      }
      if (spread_kind_[q] == kKeptMasked) {
        const KeptStencil& at = spread_stencil_[q];
        interpolate_footprint(kept_masked_[at.thread][at.offset], v, &out[3 * m]);
        continue;
      }
    }
    IbFootprint<W> fp;
    if (W != 4 && footprint<W>(&positions[3 * m], fp)) {
      interpolate_footprint(fp, v, &out[3 * m]);
      continue;
    }
    if (!interpolate_unseparable<W>(&positions[3 * m], v, &out[3 * m])) bad = std::min(bad, m);
  }
  if (bad < markers) no_fluid_near(bad, &positions[3 * bad]);
}

void ImmersedBoundary::interpolate_at_spread(const std::array<const double*, 3>& velocity,
                                             std::span<double> out) const {
  if (!spread_done_)
    throw std::logic_error("ImmersedBoundary: interpolate_at_spread before spread");
  interpolate(spread_positions_, velocity, out);
}

void ImmersedBoundary::interpolate(std::span<const double> positions,
                                   const std::array<const double*, 3>& velocity,
                                   std::span<double> out) const {
  assert(positions.size() == out.size());
  switch (kernel_) {
    case IbKernel::kPeskin2:
      return interpolate_w<2>(positions, velocity, out);
    case IbKernel::kPeskin3:
      return interpolate_w<3>(positions, velocity, out);
    case IbKernel::kPeskin4:
      return interpolate_w<4>(positions, velocity, out);
  }
}

}  // namespace dld::fluid
