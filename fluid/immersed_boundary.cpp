// SPDX-License-Identifier: MIT
#include "fluid/immersed_boundary.hpp"

#include <omp.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>
#include <string>

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
      column_solid_(static_cast<std::size_t>(lattice.px()) * lattice.py(), 0) {
  const std::size_t plane = column_solid_.size();
  const std::uint8_t* solid = lattice.solid_mask().data();
  for (int k = 0; k < lattice.nz(); ++k) {
    const std::uint8_t* layer = solid + lattice.index(-1, -1, k);
    for (std::size_t c = 0; c < plane; ++c) column_solid_[c] |= layer[c];
  }
}

namespace {
int floor_div(int a, int n) {
  return a >= 0 ? a / n : -((-a + n - 1) / n);
}
}  // namespace

bool ImmersedBoundary::stencil(const double* p, IbStencil& s) const {
  const Domain& d = lattice_.domain();
  const int nx = d.nx, ny = d.ny, nz = d.nz;
  const double h = half_width(kernel_);
  // Fold x into [0, nx) (moving by a box in x moves the frame by the shift in y).
  double X = p[0], Y = p[1], Z = p[2];
  const double wraps = std::floor(X / nx);
  X -= wraps * nx;
  Y -= wraps * d.shift;
  s.count = 0;
  double total = 0;
  // Weights per axis once per marker (the kernel is a product); z is the same for every column.
  const int i0 = static_cast<int>(std::ceil(X - 0.5 - h)),
            i1 = static_cast<int>(std::floor(X - 0.5 + h));
  const int k0 = static_cast<int>(std::ceil(Z - 0.5 - h)),
            k1 = static_cast<int>(std::floor(Z - 0.5 + h));
  int kz[4], nzk = 0;
  double wz[4];
  for (int k = k0; k <= k1 && nzk < 4; ++k) {
    int kw = k;
    if (d.walls_z) {
      if (k < 0 || k >= nz) continue;
    } else {
      kw = ((k % nz) + nz) % nz;
    }
    const double w = phi(kernel_, k + 0.5 - Z);
    if (w == 0.0) continue;
    kz[nzk] = kw;
    wz[nzk++] = w;
  }
  const std::uint8_t* solid = lattice_.solid_mask().data();
  const std::size_t px = static_cast<std::size_t>(lattice_.px());
  std::size_t zoff[4];  // padded index of (-1, -1, k) for the stencil's z layers
  for (int q = 0; q < nzk; ++q) zoff[q] = lattice_.index(-1, -1, kz[q]);
  // y weights depend on the column's box only (shifted frame): compute them once per box.
  int cached_box = 2, j0 = 0, nyj = 0;
  double wy[4];
  std::size_t row[4];  // padded offset of the stencil's y rows within a z layer, (jw + 1) * px
  int count = 0;
  for (int i = i0; i <= i1; ++i) {
    const double wx = phi(kernel_, i + 0.5 - X);
    if (wx == 0.0) continue;
    const int box = floor_div(i, nx);  // -1, 0 or +1: which neighbouring box the column is in
    const int iw = i - box * nx;
    if (box != cached_box) {
      const double Yb = Y - box * d.shift;  // the marker's y in that box's frame
      j0 = static_cast<int>(std::ceil(Yb - 0.5 - h));
      const int j1 = static_cast<int>(std::floor(Yb - 0.5 + h));
      nyj = std::min(4, j1 - j0 + 1);
      for (int q = 0; q < nyj; ++q) {
        wy[q] = phi(kernel_, j0 + q + 0.5 - Yb);
        // y is periodic: wrap any number of boxes (a marker's y is not folded into [0, ny)).
        const int jw = ((j0 + q) % ny + ny) % ny;
        row[q] = static_cast<std::size_t>(jw + 1) * px;
      }
      cached_box = box;
    }
    for (int qy = 0; qy < nyj; ++qy) {
      const double wxy = wx * wy[qy];
      if (wxy == 0.0) continue;
      // Offset of the column (iw, jw) within a z layer; the same order and arithmetic as a
      // node-by-node walk, only the index is an addition and fluid columns skip the solid check.
      const std::size_t column = row[qy] + static_cast<std::size_t>(iw + 1);
      assert(count + nzk <= IbStencil::kMax);
      if (!column_solid_[column]) {
        for (int q = 0; q < nzk; ++q) {
          const double w = wxy * wz[q];
          s.node[count + q] = zoff[q] + column;
          s.weight[count + q] = w;
          total += w;
        }
        count += nzk;
      } else {
        for (int q = 0; q < nzk; ++q) {
          const std::size_t node = zoff[q] + column;
          if (solid[node]) continue;
          const double w = wxy * wz[q];
          s.node[count] = node;
          s.weight[count] = w;
          ++count;
          total += w;
        }
      }
    }
  }
  s.count = count;
  if (total <= 0.0) return false;
  for (int n = 0; n < s.count; ++n) s.weight[n] /= total;
  return true;
}

namespace {
[[noreturn]] void no_fluid_near(std::size_t marker, const double* p) {
  throw std::runtime_error("immersed boundary: marker " + std::to_string(marker) + " at (" +
                           std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", " +
                           std::to_string(p[2]) +
                           ") has no fluid node within its kernel (inside a pillar or a wall?)");
}
}  // namespace

void ImmersedBoundary::spread(std::span<const double> positions, std::span<const double> forces,
                              const std::array<double*, 3>& field) const {
  assert(positions.size() == forces.size());
  const std::size_t n = lattice_.padded_size();
  const std::size_t markers = positions.size() / 3;
  // Markers of one cell share nodes: each thread spreads into a field of its own, then the
  // fields are added up (in thread order, so a given thread count gives the same result). The
  // per-thread fields are kept between calls and left zeroed by the reduction.
  const int threads = omp_get_max_threads();
  const std::size_t scratch_size = static_cast<std::size_t>(threads - 1) * 3 * n;
  if (scratch_.size() != scratch_size) scratch_.assign(scratch_size, 0.0);
  std::size_t bad = markers;
#pragma omp parallel num_threads(threads) reduction(min : bad)
  {
    for (int a = 0; a < 3; ++a) {
#pragma omp for schedule(static) nowait
      for (std::size_t i = 0; i < n; ++i) field[a][i] = 0.0;
    }
#pragma omp barrier
    const int t = omp_get_thread_num();
    double* own[3];
    for (int a = 0; a < 3; ++a)
      own[a] = t == 0 ? field[a] : scratch_.data() + (static_cast<std::size_t>(t - 1) * 3 + a) * n;
    IbStencil s;
#pragma omp for schedule(static)
    for (std::size_t m = 0; m < markers; ++m) {
      if (!stencil(&positions[3 * m], s)) {
        bad = std::min(bad, m);
        continue;
      }
      for (int q = 0; q < s.count; ++q)
        for (int a = 0; a < 3; ++a) own[a][s.node[q]] += s.weight[q] * forces[3 * m + a];
    }
    // (the loop's implicit barrier: every thread's field is complete)
    for (int u = 1; u < threads; ++u)
      for (int a = 0; a < 3; ++a) {
        double* other = scratch_.data() + (static_cast<std::size_t>(u - 1) * 3 + a) * n;
#pragma omp for schedule(static) nowait
        for (std::size_t i = 0; i < n; ++i) {
          field[a][i] += other[i];
          other[i] = 0.0;
        }
      }
  }
  if (bad < markers) no_fluid_near(bad, &positions[3 * bad]);
}

void ImmersedBoundary::interpolate(std::span<const double> positions,
                                   const std::array<const double*, 3>& velocity,
                                   std::span<double> out) const {
  assert(positions.size() == out.size());
  const std::size_t markers = positions.size() / 3;
  std::size_t bad = markers;  // first marker without fluid around it, if any
#pragma omp parallel for schedule(static) reduction(min : bad)
  for (std::size_t m = 0; m < markers; ++m) {
    IbStencil s;
    if (!stencil(&positions[3 * m], s)) {
      bad = std::min(bad, m);
      continue;
    }
    double u[3] = {0, 0, 0};
    for (int q = 0; q < s.count; ++q)
      for (int a = 0; a < 3; ++a) u[a] += s.weight[q] * velocity[a][s.node[q]];
    for (int a = 0; a < 3; ++a) out[3 * m + a] = u[a];
  }
  if (bad < markers) no_fluid_near(bad, &positions[3 * bad]);
}

}  // namespace dld::fluid
