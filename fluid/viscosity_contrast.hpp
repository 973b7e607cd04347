// SPDX-License-Identifier: MIT
// The inside/outside viscosity field (SPEC section 3): lattice nodes inside a cell membrane relax
// with tau_in, all other fluid nodes with tau_out. Built only when the two differ (DESIGN.md,
// "Scenes decide what runs") and rebuilt from the marker positions before every fluid step.
//
// Method: scanline voxelisation. One ray per lattice column (i + 1/2, j + 1/2) along z; every
// triangle is rasterised onto the columns its projection covers and gives one crossing height.
// A node lies inside when it has an odd number of crossings of its cell below it (even-odd rule),
// so the cost is O(triangles + inside nodes) with no search over the box. Ties (a column through
// an edge or a vertex, or grazing the silhouette) are decided for the column moved by an
// infinitesimal (eps, eps^2), with edge functions evaluated on canonically ordered edges so that
// both triangles of an edge see the same number: a closed surface never gains or loses a crossing.
//
// Units: lattice units (node (i, j, k) at (i + 1/2, j + 1/2, k + 1/2)); markers in any frame are
// folded cell by cell through the shifted periodic x faces, as the immersed boundary does.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fluid/lattice.hpp"
#include "fluid/relaxation_field.hpp"

namespace dld::fluid {

class ViscosityContrast {
 public:
  /// cell_nodes and cell_faces: nodes and triangles of every cell; faces: 3 node indices local to
  /// their cell per triangle, cell after cell. Throws std::invalid_argument if a cell has no
  /// surface (a tracer cannot carry a viscosity contrast) or the arrays disagree.
  ViscosityContrast(const Lattice& lattice, double tau_out, double tau_in,
                    std::span<const std::uint32_t> cell_nodes,
                    std::span<const std::uint32_t> cell_faces,
                    std::span<const std::uint32_t> faces);

  /// Marks the fluid nodes inside the membranes at `positions` (3 per marker, cell after cell,
  /// lattice units): tau_in there, tau_out on the nodes that were inside before and are not now.
  /// `field` is the solver's per-node relaxation field (padded size), the same one at every call:
  /// only the nodes that change side are written, so it must hold the last update's values.
  void update(std::span<const double> positions, RelaxationField& field);

  /// Padded indices of the nodes inside a membrane after the last update.
  const std::vector<std::size_t>& inside_nodes() const { return inside_; }
  /// Columns whose crossings did not pair up in the last update (an open or self-crossing
  /// surface); zero for closed meshes.
  std::size_t unpaired_columns() const { return unpaired_; }

 private:
  struct Crossing {
    std::uint64_t column;  ///< (wrapped j) << 32 | i: sorts as (j, i), decodes without division
    double z;
  };
  /// One thread's buffers: cells are independent, so each thread takes whole cells.
  struct Workspace {
    std::vector<double> folded;              ///< one cell's markers folded into the box frame
    std::vector<Crossing> crossings;         ///< one cell's crossings
    std::vector<std::size_t> inside;         ///< nodes inside this thread's cells
    std::vector<std::uint8_t> kind;          ///< per triangle of the cell: classify_triangles()
    std::vector<std::int32_t> hit_i, hit_j;  ///< its column centre when it may cover only one
    std::vector<double> hit_z;               ///< and the crossing's height there
    std::vector<Crossing> sorted;            ///< sort_crossings' buffer
    std::vector<std::size_t> bin_start;      ///< sort_crossings' bins
    std::size_t unpaired = 0;
  };
  void rasterise_cell(const double* x, std::size_t cell, Workspace& w) const;
  enum : std::uint8_t { kNoCrossing, kOneCrossing, kRasterise };
  void classify_triangles(const std::uint32_t* tris, std::size_t faces, Workspace& w) const;
  void rasterise_triangle(const std::uint32_t* tri, Workspace& w) const;
  void push_crossing(int i, int j, double z, Workspace& w) const;
  void sort_crossings(Workspace& w) const;
  void fill_cell(Workspace& w) const;

  const Lattice& lattice_;
  double tau_out_, tau_in_;
  std::vector<std::uint32_t> cell_nodes_, cell_faces_, faces_;
  std::vector<std::size_t> first_node_, first_face_;
  std::vector<Workspace> work_;      ///< one per OpenMP thread
  std::vector<std::size_t> inside_;  ///< nodes currently at tau_in
  std::vector<std::uint8_t> mark_;   ///< per padded node, see update()
  std::size_t unpaired_ = 0;
};

}  // namespace dld::fluid
