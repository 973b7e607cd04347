// SPDX-License-Identifier: MIT
// Where a marker's weights go (fluid/immersed_boundary.hpp): the node list of stencil() (any
// marker), the separable footprints (footprint(), split_footprint() across the shifted x face,
// batched_footprint() from a SIMD batch of axis weights) and their z layers by the walls.
#include <algorithm>
#include <cassert>
#include <cmath>

#include "fluid/ib_axis_batch.hpp"
#include "fluid/immersed_boundary.hpp"

namespace dld::fluid {
namespace {
int floor_div(int a, int n) {
  return a >= 0 ? a / n : -((-a + n - 1) / n);
}

/// Lane `lane` of a batch of axis weights into wx, wy, wz; false if the marker at p is not
/// finite or the box is too thin for a 4-wide support in y or z.
bool lane_weights(const Domain& d, const Peskin4AxisBatch& axes, int lane, const double* p,
                  double* wx, double* wy, double* wz) {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return false;
  if (d.ny < 4 || d.nz < 4) return false;
  for (int a = 0; a < 4; ++a) {
    wx[a] = axes.w[0][a][lane];
    wy[a] = axes.w[1][a][lane];
    wz[a] = axes.w[2][a][lane];
  }
  return true;
}

/// A marker's x folded into [0, nx) and its y moved with it (one box along x is the shift along
/// y); false if it is not finite or the box is too thin for a W-wide support in y or z.
template <int W>
bool fold_into_box(const Domain& d, const double* p, double& X, double& Y) {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return false;
  if (d.ny < W || d.nz < W) return false;  // a row or layer would repeat
  const double wraps = std::floor(p[0] / d.nx);
  X = p[0] - wraps * d.nx;
  Y = p[1] - wraps * d.shift;
  return true;
}

/// The z layers a stencil at height Z reaches: padded index of (-1, -1, k) and weight of each
/// (by walls the layers outside are left out; periodic z wraps); returns how many.
int stencil_layers(const Lattice& L, IbKernel kernel, double Z, std::size_t* zoff, double* wz) {
  const Domain& d = L.domain();
  const double h = half_width(kernel);
  const int k0 = static_cast<int>(std::ceil(Z - 0.5 - h)),
            k1 = static_cast<int>(std::floor(Z - 0.5 + h));
  int n = 0;
  for (int k = k0; k <= k1 && n < 4; ++k) {
    int kw = k;
    if (d.walls_z) {
      if (k < 0 || k >= d.nz) continue;
    } else {
      kw = ((k % d.nz) + d.nz) % d.nz;
    }
    const double w = phi(kernel, k + 0.5 - Z);
    if (w == 0.0) continue;
    zoff[n] = L.index(-1, -1, kw);
    wz[n++] = w;
  }
  return n;
}
}  // namespace

bool ImmersedBoundary::stencil(const double* p, IbStencil& s) const {
  const Domain& d = lattice_.domain();
  const int nx = d.nx, ny = d.ny;
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
  std::size_t zoff[4];  // padded index of (-1, -1, k) for the stencil's z layers
  double wz[4];
  const int nzk = stencil_layers(lattice_, kernel_, Z, zoff, wz);
  const std::uint8_t* solid = lattice_.solid_mask().data();
  const std::size_t px = static_cast<std::size_t>(lattice_.px());
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

template <int W>
int ImmersedBoundary::z_layers(double Z, double* wz, std::size_t* layer) const {
  return fit_z_layers<W>(axis_weights<W>(kernel_, Z, wz), wz, layer);
}

template <int W>
[[gnu::always_inline]] inline int ImmersedBoundary::fit_z_layers(int k0, double* wz,
                                                                 std::size_t* layer) const {
  const Domain& d = lattice_.domain();
  if (d.walls_z && (k0 < 0 || k0 + W > d.nz)) {
    // Wall layers leave the support (stencil() drops them): still separable, with those z
    // weights zero and the remaining layers renormalised. Their slots point at fluid layers.
    const int shift = k0 < 0 ? -k0 : d.nz - W - k0;  // move the window inside [0, nz)
    double w[W];
    for (int c = 0; c < W; ++c) {
      const int from = c + shift;  // the original slot of the layer now in slot c
      w[c] = from >= 0 && from < W ? wz[from] : 0.0;
    }
    for (int c = 0; c < W; ++c) wz[c] = w[c];
    k0 += shift;
  }
  const std::size_t plane = static_cast<std::size_t>(lattice_.px()) * lattice_.py();
  const int kw0 = d.walls_z || (k0 >= 0 && k0 < d.nz) ? k0 : ((k0 % d.nz) + d.nz) % d.nz;
  for (int c = 0; c < W; ++c) {
    const int kw = kw0 + c < d.nz || d.walls_z ? kw0 + c : kw0 + c - d.nz;
    layer[c] = static_cast<std::size_t>(kw + 1) * plane;
  }
  return k0;
}

template <int W>
bool ImmersedBoundary::split_footprint(const double* p, IbSplitFootprint<W>& fp) const {
  const Domain& d = lattice_.domain();
  double X = 0, Y = 0;
  if (d.nx < W || !fold_into_box<W>(d, p, X, Y)) return false;
  const int i0 = axis_weights<W>(kernel_, X, fp.wx);
  if (i0 >= 0 && i0 + W <= d.nx) return false;  // inside one box: footprint()
  z_layers<W>(p[2], fp.wz, fp.layer);
  return place_split_footprint<W>(i0, Y, nullptr, 0, fp);
}

bool ImmersedBoundary::batched_split_footprint(const Peskin4AxisBatch& axes, int lane,
                                               const double* p, IbSplitFootprint<4>& fp) const {
  const Domain& d = lattice_.domain();
  double wy[4];
  if (d.nx < 4 || !lane_weights(d, axes, lane, p, fp.wx, wy, fp.wz)) return false;
  const int i0 = static_cast<int>(axes.first[0][lane]);  // finite: lane_weights checked
  if (i0 >= 0 && i0 + 4 <= d.nx) return false;           // inside one box: footprint()
  fit_z_layers<4>(static_cast<int>(axes.first[2][lane]), fp.wz, fp.layer);
  const double wraps = std::floor(p[0] / d.nx);  // as peskin4_axis_batch folds it
  return place_split_footprint<4>(i0, p[1] - wraps * d.shift, wy,
                                  static_cast<int>(axes.first[1][lane]), fp);
}

// The rows of each part: the part in the marker's own box (box 0) takes wy_box0 and j0_box0 when
// given (the batch's y weights, computed in that frame), the other computes its own.
template <int W>
bool ImmersedBoundary::place_split_footprint(int i0, double Y, const double* wy_box0, int j0_box0,
                                             IbSplitFootprint<W>& fp) const {
  const Domain& d = lattice_.domain();
  const int box0 = i0 < 0 ? -1 : 0;  // the box of the first column; the rest are in box0 + 1
  fp.split = (box0 + 1) * d.nx - i0;
  const auto px = static_cast<std::size_t>(lattice_.px());
  double sy[2] = {0, 0};
  for (int part = 0; part < 2; ++part) {
    const int box = box0 + part;
    int j0 = j0_box0;
    if (box == 0 && wy_box0 != nullptr) {
      for (int b = 0; b < W; ++b) fp.wy[part][b] = wy_box0[b];
    } else {
      j0 = axis_weights<W>(kernel_, Y - box * d.shift, fp.wy[part]);
    }
    const int jw0 = j0 >= 0 && j0 < d.ny ? j0 : ((j0 % d.ny) + d.ny) % d.ny;
    const int first = part == 0 ? i0 - box * d.nx : 0;  // the part's first column in its box
    fp.x0[part] = static_cast<std::size_t>(first) + 1;
    const int columns = part == 0 ? fp.split : W - fp.split;
    for (int b = 0; b < W; ++b) {
      sy[part] += fp.wy[part][b];
      const int jw = jw0 + b < d.ny ? jw0 + b : jw0 + b - d.ny;
      fp.row[part][b] = static_cast<std::size_t>(jw + 1) * px;
      for (int a = 0; a < columns; ++a)
        if (column_solid_[fp.row[part][b] + fp.x0[part] + static_cast<std::size_t>(a)])
          return false;
    }
  }
  double sz = 0, total = 0;
  for (int c = 0; c < W; ++c) sz += fp.wz[c];
  for (int a = 0; a < W; ++a) total += fp.wx[a] * sy[a < fp.split ? 0 : 1];
  const double inv = 1.0 / (total * sz);
  for (double& w : fp.wx) w *= inv;
  return true;
}

template bool ImmersedBoundary::split_footprint<2>(const double*, IbSplitFootprint<2>&) const;
template bool ImmersedBoundary::split_footprint<3>(const double*, IbSplitFootprint<3>&) const;
template bool ImmersedBoundary::split_footprint<4>(const double*, IbSplitFootprint<4>&) const;

template <int W>
bool ImmersedBoundary::footprint(const double* p, IbFootprint<W>& fp) const {
  const Domain& d = lattice_.domain();
  double X = 0, Y = 0;
  if (!fold_into_box<W>(d, p, X, Y)) return false;
  const int i0 = axis_weights<W>(kernel_, X, fp.wx);
  if (i0 < 0 || i0 + W > d.nx) return false;  // across the shifted x face
  const int k0 = axis_weights<W>(kernel_, p[2], fp.wz);
  return place_footprint<W>(i0, axis_weights<W>(kernel_, Y, fp.wy), k0, fp);
}

template <int W>
[[gnu::always_inline]] inline bool ImmersedBoundary::place_footprint(int i0, int j0, int k0,
                                                                     IbFootprint<W>& fp) const {
  const Domain& d = lattice_.domain();
  if (i0 < 0 || i0 + W > d.nx) return false;  // across the shifted x face
  fit_z_layers<W>(k0, fp.wz, fp.layer);
  const int jw0 = j0 >= 0 && j0 < d.ny ? j0 : ((j0 % d.ny) + d.ny) % d.ny;
  if (block_solid_[static_cast<std::size_t>(jw0) * d.nx + i0]) return false;
  const auto px = static_cast<std::size_t>(lattice_.px());
  double sx = 0, sy = 0, sz = 0;
  for (int a = 0; a < W; ++a) {
    sx += fp.wx[a], sy += fp.wy[a], sz += fp.wz[a];
    const int jw = jw0 + a < d.ny ? jw0 + a : jw0 + a - d.ny;  // y is periodic
    fp.row[a] = static_cast<std::size_t>(jw + 1) * px;
  }
  // The weights sum to one analytically; normalising as stencil() does keeps spreading
  // conservative and interpolation a weighted mean to round-off.
  const double inv = 1.0 / (sx * sy * sz);
  for (double& w : fp.wx) w *= inv;
  fp.x0 = static_cast<std::size_t>(i0) + 1;
  return true;
}

bool ImmersedBoundary::batched_footprint(const Peskin4AxisBatch& axes, int lane, const double* p,
                                         IbFootprint<4>& fp) const {
  return lane_footprint(axes, lane, p, fp);
}

[[gnu::always_inline]] inline bool ImmersedBoundary::lane_footprint(const Peskin4AxisBatch& axes,
                                                                    int lane, const double* p,
                                                                    IbFootprint<4>& fp) const {
  if (!lane_weights(lattice_.domain(), axes, lane, p, fp.wx, fp.wy, fp.wz)) return false;
  return place_footprint<4>(static_cast<int>(axes.first[0][lane]),
                            static_cast<int>(axes.first[1][lane]),
                            static_cast<int>(axes.first[2][lane]), fp);
}

void ImmersedBoundary::batched_footprints(const Peskin4AxisBatch& axes, int count,
                                          const double* positions, const std::uint32_t* order,
                                          IbFootprint<4>* fp, bool* separable) const {
  for (int lane = 0; lane < count; ++lane)
    separable[lane] =
        lane_footprint(axes, lane, &positions[3 * static_cast<std::size_t>(order[lane])], fp[lane]);
}

// By the pillar: its columns are solid at every height, so stencil()'s dropping of solid nodes
// zeroes whole columns, and its renormalisation divides by (sum over fluid columns of wx wy) x
// (sum of wz). The same nodes and weights as stencil(), up to the order of the sums.
template <int W>
bool ImmersedBoundary::masked_footprint(const double* p, IbMaskedFootprint<W>& fp) const {
  double X = 0, Y = 0;
  if (!fold_into_box<W>(lattice_.domain(), p, X, Y)) return false;
  double wx[W], wy[W];
  const int i0 = axis_weights<W>(kernel_, X, wx);
  const int j0 = axis_weights<W>(kernel_, Y, wy);
  return place_masked_footprint<W>(i0, j0, axis_weights<W>(kernel_, p[2], fp.wz), wx, wy, fp);
}

bool ImmersedBoundary::batched_masked_footprint(const Peskin4AxisBatch& axes, int lane,
                                                const double* p, IbMaskedFootprint<4>& fp) const {
  double wx[4], wy[4];
  if (!lane_weights(lattice_.domain(), axes, lane, p, wx, wy, fp.wz)) return false;
  return place_masked_footprint<4>(static_cast<int>(axes.first[0][lane]),
                                   static_cast<int>(axes.first[1][lane]),
                                   static_cast<int>(axes.first[2][lane]), wx, wy, fp);
}

template <int W>
bool ImmersedBoundary::place_masked_footprint(int i0, int j0, int k0, const double* wx,
                                              const double* wy, IbMaskedFootprint<W>& fp) const {
  const Domain& d = lattice_.domain();
  if (i0 < 0 || i0 + W > d.nx) return false;  // across the shifted x face
  fit_z_layers<W>(k0, fp.wz, fp.layer);
  const int jw0 = j0 >= 0 && j0 < d.ny ? j0 : ((j0 % d.ny) + d.ny) % d.ny;
  const auto px = static_cast<std::size_t>(lattice_.px());
  fp.x0 = static_cast<std::size_t>(i0) + 1;
  double sxy = 0, sz = 0;
  for (int b = 0; b < W; ++b) {
    const int jw = jw0 + b < d.ny ? jw0 + b : jw0 + b - d.ny;  // y is periodic
    fp.row[b] = static_cast<std::size_t>(jw + 1) * px;
    fp.wy[b] = wy[b];
    double sx = 0;
    for (int a = 0; a < W; ++a) {
      const std::size_t column = fp.row[b] + fp.x0 + static_cast<std::size_t>(a);
      if (column_solid_[column] && !column_all_solid_[column]) return false;  // stencil()
      fp.wx[b][a] = column_solid_[column] ? 0.0 : wx[a];
      sx += fp.wx[b][a];
    }
    sxy += sx * wy[b];
  }
  for (int c = 0; c < W; ++c) sz += fp.wz[c];
  const double total = sxy * sz;
  if (!(total > 0.0)) return false;  // no fluid node in reach
  const double inv = 1.0 / total;
  for (int b = 0; b < W; ++b)
    for (int a = 0; a < W; ++a) fp.wx[b][a] *= inv;
  return true;
}

template bool ImmersedBoundary::masked_footprint<2>(const double*, IbMaskedFootprint<2>&) const;
template bool ImmersedBoundary::masked_footprint<3>(const double*, IbMaskedFootprint<3>&) const;
template bool ImmersedBoundary::masked_footprint<4>(const double*, IbMaskedFootprint<4>&) const;

template bool ImmersedBoundary::footprint<2>(const double*, IbFootprint<2>&) const;
template bool ImmersedBoundary::footprint<3>(const double*, IbFootprint<3>&) const;
template bool ImmersedBoundary::footprint<4>(const double*, IbFootprint<4>&) const;

}  // namespace dld::fluid
