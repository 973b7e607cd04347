// SPDX-License-Identifier: MIT
#include "fluid/viscosity_contrast.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dld::fluid {

namespace {

struct P2 {
  double x, y;
  std::uint32_t id;  ///< node index within the cell: orders the edges canonically
};

/// Edge function of edge a -> b at p, evaluated with the endpoints in canonical order (lower node
/// index first) and negated back: the two triangles of an edge get exactly opposite numbers, and
/// a column through a vertex gets exactly 0 (the file is built without fused multiply-add).
/// Coordinates and node ids held apart, ids as doubles (exact below 2^53), so that the SIMD loop
/// of classify_triangles has one double per lane; no branches.
inline double edge_of(double ax, double ay, double aid, double bx, double by, double bid, double px,
                      double py) {
  const bool a_lo = aid < bid;
  const double lx = a_lo ? ax : bx, ly = a_lo ? ay : by;
  const double hx = a_lo ? bx : ax, hy = a_lo ? by : ay;
  const double e = (hx - lx) * (py - ly) - (hy - ly) * (px - lx);
  return a_lo ? e : -e;
}

/// Whether a column exactly on edge a -> b of a counter-clockwise triangle counts as inside it:
/// the answer for the column moved by (eps, eps^2), eps -> 0 (simulation of simplicity,
/// Edelsbrunner & Muecke 1990, ACM TOG 9:66). The edge function then grows by
/// -(b.y - a.y) eps + (b.x - a.x) eps^2. The moved column is a generic point, so a closed surface
/// crosses it an even number of times: ties on shared edges, at vertices and on the silhouette
/// (where the ray grazes the surface) all pair up. (Bitwise operators: no branches.)
inline bool owns_ties_of(double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay;
  return (dy < 0.0) | ((dy == 0.0) & (dx > 0.0));
}

inline bool covers(double e, bool ties) {
  return (e > 0.0) | ((e == 0.0) & ties);
}

// The same on the triangle walk's points.
double edge(const P2& a, const P2& b, double px, double py) {
  return edge_of(a.x, a.y, a.id, b.x, b.y, b.id, px, py);
}
bool owns_ties(const P2& a, const P2& b) {
  return owns_ties_of(a.x, a.y, b.x, b.y);
}

}  // namespace

ViscosityContrast::ViscosityContrast(const Lattice& lattice, double tau_out, double tau_in,
                                     std::span<const std::uint32_t> cell_nodes,
                                     std::span<const std::uint32_t> cell_faces,
                                     std::span<const std::uint32_t> faces)
    : lattice_(lattice),
      tau_out_(tau_out),
      tau_in_(tau_in),
      cell_nodes_(cell_nodes.begin(), cell_nodes.end()),
      cell_faces_(cell_faces.begin(), cell_faces.end()),
      faces_(faces.begin(), faces.end()) {
  if (cell_faces_.size() != cell_nodes_.size()) {
    throw std::invalid_argument("viscosity contrast: face counts for " +
                                std::to_string(cell_faces_.size()) + " cells, node counts for " +
                                std::to_string(cell_nodes_.size()));
  }
  std::size_t node = 0, face = 0;
  for (std::size_t c = 0; c < cell_nodes_.size(); ++c) {
    if (cell_faces_[c] < 4) {
      throw std::invalid_argument(
          "viscosity contrast: cell " + std::to_string(c) + " has " +
          std::to_string(cell_faces_[c]) +
          " triangles; the inside/outside field needs closed membrane surfaces (tracers have "
          "none: use viscosity_ratio = 1)");
    }
    first_node_.push_back(node);
    first_face_.push_back(face);
    node += cell_nodes_[c];
    face += cell_faces_[c];
  }
  if (3 * face != faces_.size()) {
    throw std::invalid_argument("viscosity contrast: " + std::to_string(faces_.size()) +
                                " face indices for " + std::to_string(face) + " triangles");
  }
}

void ViscosityContrast::update(std::span<const double> positions, RelaxationField& field) {
  const RelaxationField::Value outside = field.value_of(tau_out_), inside = field.value_of(tau_in_);
  const std::size_t total_nodes = first_node_.empty() ? 0 : first_node_.back() + cell_nodes_.back();
  if (positions.size() != 3 * total_nodes) {
    throw std::invalid_argument("viscosity contrast: " + std::to_string(positions.size() / 3) +
                                " markers, the cells have " + std::to_string(total_nodes));
  }
  // Cells are independent and never share a node: each thread rasterises and marks whole cells.
  const int threads = omp_get_max_threads();
  if (work_.size() != static_cast<std::size_t>(threads)) {
    work_.resize(static_cast<std::size_t>(threads));
  }
  const auto cells = static_cast<std::int64_t>(cell_nodes_.size());
  const auto was_inside = static_cast<std::int64_t>(inside_.size());
  // Only the nodes that change side are written to the field (a step moves a membrane by a small
  // part of a spacing, so few do): mark_ has bit 0 for the nodes at tau_in since the last update
  // and gets bit 1 for those inside now.
  if (mark_.size() != field.size()) mark_.assign(field.size(), 0);
  std::uint8_t* mark = mark_.data();
#pragma omp parallel num_threads(threads)
  {
    Workspace& w = work_[static_cast<std::size_t>(omp_get_thread_num())];
    w.inside.clear();
    w.unpaired = 0;
    // Cells differ in cost (one across the x face is rasterised in two boxes): dynamic. The
    // field does not depend on which thread takes which cell.
#pragma omp for schedule(dynamic, 1)
    for (std::int64_t c = 0; c < cells; ++c) {
      const auto cell = static_cast<std::size_t>(c);
      rasterise_cell(positions.data() + 3 * first_node_[cell], cell, w);
      fill_cell(w);
    }
    for (std::size_t n : w.inside) mark[n] |= 2;
#pragma omp barrier
      // Inside before and not now: back to tau_out (the loop's barrier follows).
#pragma omp for schedule(static)
    for (std::int64_t q = 0; q < was_inside; ++q) {
      const std::size_t n = inside_[static_cast<std::size_t>(q)];
      if (mark[n] == 1) {
        field.set(n, outside);
        mark[n] = 0;
      }
    }
    for (std::size_t n : w.inside) {
      if (mark[n] == 2) field.set(n, inside);  // inside now and not before
      mark[n] = 1;
    }
  }
  inside_.clear();
  unpaired_ = 0;
  for (const Workspace& w : work_) {
    inside_.insert(inside_.end(), w.inside.begin(), w.inside.end());
    unpaired_ += w.unpaired;
  }
}

// Folds the cell into the box as one piece (by its mean x, so it is never torn apart), then
// rasterises its triangles. They are classified first, SIMD across triangles: most triangles of a
// fine mesh cover no column centre or exactly one, whose crossing comes from that pass; the others
// (and those reaching past an x face of the box) take rasterise_triangle(). Triangles are visited
// in mesh order either way, so the crossings are the same numbers in the same order as the
// triangle-by-triangle walk gives.
void ViscosityContrast::rasterise_cell(const double* x, std::size_t cell, Workspace& w) const {
  const Domain& d = lattice_.domain();
  const std::size_t n = cell_nodes_[cell];
  double mean_x = 0;
  for (std::size_t m = 0; m < n; ++m) {
    mean_x += x[3 * m];
  }
  const double wraps = std::floor(mean_x / static_cast<double>(n) / d.nx);
  w.folded.resize(3 * n);
  for (std::size_t m = 0; m < n; ++m) {
    w.folded[3 * m] = x[3 * m] - wraps * d.nx;
    w.folded[3 * m + 1] = x[3 * m + 1] - wraps * d.shift;
    w.folded[3 * m + 2] = x[3 * m + 2];
  }
  w.crossings.clear();
  const std::size_t faces = cell_faces_[cell];
  const std::uint32_t* tris = faces_.data() + 3 * first_face_[cell];
  classify_triangles(tris, faces, w);
  for (std::size_t f = 0; f < faces; ++f) {
    if (w.kind[f] == kOneCrossing) {
      push_crossing(w.hit_i[f], w.hit_j[f], w.hit_z[f], w);
    } else if (w.kind[f] == kRasterise) {
      rasterise_triangle(tris + 3 * f, w);
    }
  }
}

// Per triangle inside the box in x (the walk's box 0): whether its x-y extent holds no column
// centre, one (then the crossing, if the triangle covers it, with rasterise_triangle()'s
// arithmetic step for step: the same orientation swap, tie rules and interpolation), or more;
// kRasterise for more and for triangles reaching past an x face.
void ViscosityContrast::classify_triangles(const std::uint32_t* tris, std::size_t faces,
                                           Workspace& w) const {
  const double* X = w.folded.data();
  const auto nx = static_cast<double>(lattice_.domain().nx);
  w.kind.resize(faces);
  w.hit_i.resize(faces);
  w.hit_j.resize(faces);
  w.hit_z.resize(faces);
  std::uint8_t* kind = w.kind.data();
  std::int32_t* hit_i = w.hit_i.data();
  std::int32_t* hit_j = w.hit_j.data();
  double* hit_z = w.hit_z.data();
#pragma omp simd
  for (std::size_t f = 0; f < faces; ++f) {
    const std::uint32_t id0 = tris[3 * f], id1 = tris[3 * f + 1], id2 = tris[3 * f + 2];
    // 32-bit offsets: GCC 12 gathers with them, not with zero-extended 64-bit ones (a cell has
    // far fewer than 2^31 / 3 nodes).
    const auto a = 3 * static_cast<std::int32_t>(id0), b = 3 * static_cast<std::int32_t>(id1),
               c = 3 * static_cast<std::int32_t>(id2);
    const double x0 = X[a], y0 = X[a + 1], z0 = X[a + 2], x1 = X[b], y1 = X[b + 1], z1 = X[b + 2];
    const double x2 = X[c], y2 = X[c + 1], z2 = X[c + 2];
    // Node ids as doubles (exact below 2^53): every lane of the loop is then one double.
    const double n0 = id0, n1 = id1, n2 = id2;
    const double xmin = std::min(x0, std::min(x1, x2)), xmax = std::max(x0, std::max(x1, x2));
    const double i0 = std::ceil(xmin - 0.5), i1 = std::floor(xmax - 0.5);
    const double j0 = std::ceil(std::min(y0, std::min(y1, y2)) - 0.5);
    const double j1 = std::floor(std::max(y0, std::max(y1, y2)) - 0.5);
    const double px = i0 + 0.5, py = j0 + 0.5;
    // Counter-clockwise: vertices 1 and 2 (coordinates, ids, heights) swapped when clockwise.
    const double area = edge_of(x0, y0, n0, x1, y1, n1, x2, y2);
    const bool cw = area < 0.0;
    const double ax = cw ? x2 : x1, ay = cw ? y2 : y1, az = cw ? z2 : z1;
    const double bx = cw ? x1 : x2, by = cw ? y1 : y2, bz = cw ? z1 : z2;
    const double an = cw ? n2 : n1, bn = cw ? n1 : n2;
    const double e0 = edge_of(ax, ay, an, bx, by, bn, px, py);
    const double e1 = edge_of(bx, by, bn, x0, y0, n0, px, py);
    const double e2 = edge_of(x0, y0, n0, ax, ay, an, px, py);
    const bool hit = (area != 0.0) & covers(e0, owns_ties_of(ax, ay, bx, by)) &
                     covers(e1, owns_ties_of(bx, by, x0, y0)) &
                     covers(e2, owns_ties_of(x0, y0, ax, ay));
    // A triangle reaching past the box's x faces is walked box by box (not NaN-safe otherwise).
    const bool in_box = (xmin >= 0.0) & (xmax < nx);
    const bool none = (i0 > i1) | (j0 > j1), one = (i0 == i1) & (j0 == j1);
    const int k = one & hit ? kOneCrossing : kNoCrossing;
    kind[f] = static_cast<std::uint8_t>(!in_box ? kRasterise
                                                : (none ? kNoCrossing : (one ? k : kRasterise)));
    hit_i[f] = static_cast<std::int32_t>(i0);
    hit_j[f] = static_cast<std::int32_t>(j0);
    hit_z[f] = (e0 * z0 + e1 * az + e2 * bz) / (e0 + e1 + e2);
  }
}

void ViscosityContrast::push_crossing(int i, int j, double z, Workspace& w) const {
  const Domain& d = lattice_.domain();
  // y is periodic; a cell is never more than a box away in y, so no modulo is needed.
  int jw = j < 0 ? j + d.ny : (j >= d.ny ? j - d.ny : j);
  if (jw < 0 || jw >= d.ny) {
    jw = ((j % d.ny) + d.ny) % d.ny;
  }
  w.crossings.push_back(
      {(static_cast<std::uint64_t>(jw) << 32) | static_cast<std::uint32_t>(i), z});
}

// One triangle (node indices into w.folded) in every box frame its x extent reaches: columns
// beyond x = nx belong to the next box, whose frame is lower by the shift (as in
// ImmersedBoundary::stencil).
void ViscosityContrast::rasterise_triangle(const std::uint32_t* tri, Workspace& w) const {
  const Domain& d = lattice_.domain();
  const double inv_nx = 1.0 / d.nx;
  const double* v[3] = {&w.folded[3 * std::size_t{tri[0]}], &w.folded[3 * std::size_t{tri[1]}],
                        &w.folded[3 * std::size_t{tri[2]}]};
  const double xmin = std::min({v[0][0], v[1][0], v[2][0]});
  const double xmax = std::max({v[0][0], v[1][0], v[2][0]});
  // The boxes the x extent reaches, without integer divisions: a box that rounding adds or
  // drops is met only within round-off of its edge, 1/2 away from its first column centre, so
  // it has no crossing either way.
  const int box_hi = static_cast<int>(std::floor(xmax * inv_nx));
  for (int box = static_cast<int>(std::floor(xmin * inv_nx)); box <= box_hi; ++box) {
    P2 p[3];
    for (int q = 0; q < 3; ++q) {
      p[q] = {v[q][0] - box * d.nx, v[q][1] - box * d.shift, tri[q]};
    }
    const int i0 = std::max(0, static_cast<int>(std::ceil(xmin - box * d.nx - 0.5)));
    const int i1 = std::min(d.nx - 1, static_cast<int>(std::floor(xmax - box * d.nx - 0.5)));
    const double ymin = std::min({p[0].y, p[1].y, p[2].y});
    const double ymax = std::max({p[0].y, p[1].y, p[2].y});
    const int j0 = static_cast<int>(std::ceil(ymin - 0.5));
    const int j1 = static_cast<int>(std::floor(ymax - 0.5));
    // Most triangles of a fine mesh cover no column centre: nothing to rasterise.
    if (i0 > i1 || j0 > j1) {
      continue;
    }
    double z[3] = {v[0][2], v[1][2], v[2][2]};
    // Counter-clockwise in the x-y projection; an edge-on triangle crosses no column.
    const double area = edge(p[0], p[1], p[2].x, p[2].y);
    if (area == 0.0) {
      continue;
    }
    if (area < 0.0) {
      std::swap(p[1], p[2]);
      std::swap(z[1], z[2]);
    }
    const bool tie01 = owns_ties(p[0], p[1]), tie12 = owns_ties(p[1], p[2]),
               tie20 = owns_ties(p[2], p[0]);
    for (int i = i0; i <= i1; ++i) {
      const double px = i + 0.5;
      for (int j = j0; j <= j1; ++j) {
        const double py = j + 0.5;
        const double e0 = edge(p[1], p[2], px, py);  // weight of vertex 0
        const double e1 = edge(p[2], p[0], px, py);
        const double e2 = edge(p[0], p[1], px, py);
        if (!covers(e0, tie12) || !covers(e1, tie20) || !covers(e2, tie01)) {
          continue;
        }
        push_crossing(i, j, (e0 * z[0] + e1 * z[1] + e2 * z[2]) / (e0 + e1 + e2), w);
      }
    }
  }
}

// Orders the crossings by column (j, i) and, within a column, by height: a counting sort over the
// columns the cell covers (a few hundred; a comparison sort of its ~10^3 crossings cost more than
// finding them), then an insertion sort of each column's few heights.
void ViscosityContrast::sort_crossings(Workspace& w) const {
  auto& c = w.crossings;
  if (c.empty()) {
    return;
  }
  std::uint32_t i_lo = ~0u, i_hi = 0, j_lo = ~0u, j_hi = 0;
  for (const Crossing& x : c) {
    const auto i = static_cast<std::uint32_t>(x.column & 0xffffffffu);
    const auto j = static_cast<std::uint32_t>(x.column >> 32);
    i_lo = std::min(i_lo, i), i_hi = std::max(i_hi, i);
    j_lo = std::min(j_lo, j), j_hi = std::max(j_hi, j);
  }
  const std::size_t width = i_hi - i_lo + 1, bins = width * (j_hi - j_lo + 1);
  auto bin = [&](const Crossing& x) {
    return (static_cast<std::size_t>(x.column >> 32) - j_lo) * width +
           (static_cast<std::size_t>(x.column & 0xffffffffu) - i_lo);
  };
  w.bin_start.assign(bins + 1, 0);
  for (const Crossing& x : c) {
    ++w.bin_start[bin(x) + 1];
  }
  for (std::size_t b = 1; b <= bins; ++b) {
    w.bin_start[b] += w.bin_start[b - 1];
  }
  w.sorted.resize(c.size());
  for (const Crossing& x : c) {
    w.sorted[w.bin_start[bin(x)]++] = x;
  }
  // Each bin is now [bin_start[b - 1], bin_start[b]); sort its heights.
  std::size_t begin = 0;
  for (std::size_t b = 0; b < bins; ++b) {
    const std::size_t end = w.bin_start[b];
    for (std::size_t q = begin + 1; q < end; ++q) {
      const Crossing x = w.sorted[q];
      std::size_t r = q;
      for (; r > begin && w.sorted[r - 1].z > x.z; --r) {
        w.sorted[r] = w.sorted[r - 1];
      }
      w.sorted[r] = x;
    }
    begin = end;
  }
  c.swap(w.sorted);
}

// Sorts the crossings by column and height and marks the nodes between the 1st and 2nd, 3rd and
// 4th, ... crossing of each column. z is unwrapped, so a cell across a periodic z face still pairs
// up; its nodes are wrapped when marked.
void ViscosityContrast::fill_cell(Workspace& w) const {
  const Domain& d = lattice_.domain();
  const std::uint8_t* solid = lattice_.solid_mask().data();
  sort_crossings(w);
  std::size_t a = 0;
  while (a < w.crossings.size()) {
    std::size_t b = a;
    while (b < w.crossings.size() && w.crossings[b].column == w.crossings[a].column) {
      ++b;
    }
    if ((b - a) % 2 != 0) {
      ++w.unpaired;
    }
    const int i = static_cast<int>(w.crossings[a].column & 0xffffffffu);
    const int j = static_cast<int>(w.crossings[a].column >> 32);
    for (std::size_t q = a; q + 1 < b; q += 2) {
      const int k0 = static_cast<int>(std::ceil(w.crossings[q].z - 0.5));
      const int k1 = static_cast<int>(std::floor(w.crossings[q + 1].z - 0.5));
      for (int k = k0; k <= k1; ++k) {
        int kw = k;
        if (d.walls_z) {
          if (k < 0 || k >= d.nz) {
            continue;
          }
        } else {
          kw = ((k % d.nz) + d.nz) % d.nz;
        }
        const std::size_t node = lattice_.index(i, j, kw);
        if (!solid[node]) {
          w.inside.push_back(node);
        }
      }
    }
    a = b;
  }
}

}  // namespace dld::fluid
