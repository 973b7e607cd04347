// SPDX-License-Identifier: MIT
// Immersed-boundary coupling on a Lattice: spreading marker forces to the lattice and
// interpolating the lattice velocity at the markers with the same weights (Peskin 2002).
// Positions are in lattice units in the box frame (node (i, j, k) at (i + 1/2, j + 1/2, k + 1/2));
// a marker outside the box is folded in through the shifted periodic faces first.
//
// Across the shifted x face, the stencil columns beyond x = nx belong to the next box, whose y
// coordinate is lower by the shift: their y weights are computed about Y - d (Y + d beyond x = 0).
// This keeps every column's y weights summing to one, also for a fractional shift.
// Stencil nodes that are solid (walls, pillar) are dropped and the remaining weights rescaled to
// sum to one, so spreading conserves the total force exactly and interpolation is a weighted
// mean of fluid velocities.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fluid/ib_axis_batch.hpp"
#include "fluid/ib_footprint.hpp"
#include "fluid/ib_kernel.hpp"
#include "fluid/ib_masked_footprint.hpp"
#include "fluid/lattice.hpp"

namespace dld::fluid {

/// The lattice nodes (padded indices) a marker touches and their normalised weights.
struct IbStencil {
  static constexpr int kMax = 64;
  int count = 0;
  std::array<std::size_t, kMax> node{};
  std::array<double, kMax> weight{};
};

class ImmersedBoundary {
 public:
  ImmersedBoundary(const Lattice& lattice, IbKernel kernel);

  IbKernel kernel() const { return kernel_; }
  /// Stencil of a marker at position p (lattice units, any frame); false if no fluid node is
  /// within the kernel's reach (the marker is deep inside a solid).
  bool stencil(const double* p, IbStencil& s) const;

  /// Adds the marker forces (3 per marker, lattice force units) to the per-node force field.
  /// positions and forces: 3 x markers doubles, node-major. `field` is zeroed first.
  void spread(std::span<const double> positions, std::span<const double> forces,
              const std::array<double*, 3>& field) const;
  /// Velocity at each marker from the per-node velocity arrays (padded size, lattice units).
  void interpolate(std::span<const double> positions, const std::array<const double*, 3>& velocity,
                   std::span<double> out) const;
  /// interpolate() at the positions of the last spread (its weights; [coupling] spread_held),
  /// one velocity per marker of that spread. std::logic_error before any spread.
  void interpolate_at_spread(const std::array<const double*, 3>& velocity,
                             std::span<double> out) const;

  /// The separable footprint of a marker (fluid/ib_footprint.hpp) with W = the kernel's width;
  /// false when the marker needs stencil() instead: its support crosses the shifted x face or a
  /// z wall, or reaches a solid node. Both give the same weights up to round-off.
  template <int W>
  bool footprint(const double* p, IbFootprint<W>& fp) const;
  /// The same for a marker whose support crosses the shifted x face; false when it does not, or
  /// reaches a solid node.
  template <int W>
  bool split_footprint(const double* p, IbSplitFootprint<W>& fp) const;
  /// footprint<4>() of the marker at p (Peskin 4) from its lane of a batch of axis weights
  /// (fluid/ib_axis_batch.hpp): the same weights and nodes, bit for bit.
  bool batched_footprint(const Peskin4AxisBatch& axes, int lane, const double* p,
                         IbFootprint<4>& fp) const;
  /// batched_footprint() of every lane of a batch of the markers order[0..count) of `positions`,
  /// into fp[lane] and separable[lane].
  void batched_footprints(const Peskin4AxisBatch& axes, int count, const double* positions,
                          const std::uint32_t* order, IbFootprint<4>* fp, bool* separable) const;
  /// The footprint of a marker inside one box whose support reaches columns that are solid at
  /// every height (the pillar; fluid/ib_masked_footprint.hpp); false when it crosses the shifted
  /// x face, reaches a column solid at some heights only, or no fluid node. stencil()'s weights
  /// up to round-off.
  template <int W>
  bool masked_footprint(const double* p, IbMaskedFootprint<W>& fp) const;
  /// split_footprint<4>() from lane `lane` of a batch of axis weights: the same bits.
  bool batched_split_footprint(const Peskin4AxisBatch& axes, int lane, const double* p,
                               IbSplitFootprint<4>& fp) const;
  /// masked_footprint<4>() from lane `lane` of a batch of axis weights: the same bits.
  bool batched_masked_footprint(const Peskin4AxisBatch& axes, int lane, const double* p,
                                IbMaskedFootprint<4>& fp) const;

 private:
  /// z weights and layer offsets of a support (wall layers zero-weighted, see footprint());
  /// returns the first layer.
  template <int W>
  int z_layers(double Z, double* wz, std::size_t* layer) const;
  /// The same from the support's first layer k0 and its weights wz (adjusted in place).
  template <int W>
  int fit_z_layers(int k0, double* wz, std::size_t* layer) const;
  /// The rest of footprint() once the axis weights (fp.wx, wy, wz, unnormalised) and the
  /// supports' first nodes (i0, j0, k0; x folded into the box) are known.
  template <int W>
  bool place_footprint(int i0, int j0, int k0, IbFootprint<W>& fp) const;
  /// The rest of split_footprint() once the x and z weights are in fp (z layers fitted): the
  /// rows of both parts; Y is the marker's y with x folded into the box.
  template <int W>
  bool place_split_footprint(int i0, double Y, const double* wy_box0, int j0_box0,
                             IbSplitFootprint<W>& fp) const;
  /// The rest of masked_footprint() once the axis weights (fp.wz; wx, wy; unnormalised) and the
  /// supports' first nodes are known.
  template <int W>
  bool place_masked_footprint(int i0, int j0, int k0, const double* wx, const double* wy,
                              IbMaskedFootprint<W>& fp) const;
  /// batched_footprint(), inlined into batched_footprints().
  bool lane_footprint(const Peskin4AxisBatch& axes, int lane, const double* p,
                      IbFootprint<4>& fp) const;
  template <int W>
  bool spread_unseparable(std::uint32_t q, int thread, const double* p, const double* force,
                          double* const out[3]) const;
  bool spread_batched_unseparable(const Peskin4AxisBatch& axes, int lane, std::uint32_t q,
                                  int thread, const double* p, const double* force,
                                  double* const out[3]) const;
  template <int W>
  void spread_w(std::span<const double> positions, std::span<const double> forces,
                const std::array<double*, 3>& field) const;
  struct KeptStencil {
    std::uint32_t thread, offset, count;  ///< where in kept_nodes_/kept_weights_ of which thread
  };
  /// Copies stencil s of a marker spread by `thread` into that thread's kept nodes and weights.
  void keep_stencil(const IbStencil& s, int thread, KeptStencil& kept) const;
  /// The same for a masked footprint (count 1, into that thread's kept_masked_).
  void keep_masked(const IbMaskedFootprint<4>& fp, int thread, KeptStencil& kept) const;
  void interpolate_kept_stencil(const KeptStencil& kept, const double* const v[3],
                                double* out) const;
  template <int W>
  bool interpolate_unseparable(const double* p, const double* const v[3], double* out) const;
  void interpolate_moved(std::span<const double> positions, const double* const v[3],
                         std::span<double> out) const;
  template <int W>
  void interpolate_w(std::span<const double> positions,
                     const std::array<const double*, 3>& velocity, std::span<double> out) const;
  /// first_ and bin_ of every marker (in parallel): its support's first x column and its (x, y)
  /// column bin.
  void locate_markers(std::span<const double> positions, int width) const;
  /// Fills by_column_: the markers sorted by bin_ (counting sort).
  void sort_by_column() const;
  /// Splits the markers among `threads` x slabs for spreading without write conflicts: fills
  /// order_ (marker indices, group after group, in column order within a group) and group_start_
  /// (2 threads + 1 entries).
  void group_markers(int threads, int width) const;

  const Lattice& lattice_;
  IbKernel kernel_;
  /// Per (i, j) column of the padded x-y plane (index (j + 1) * px + i + 1): 1 if any node of the
  /// column is solid, so stencil() checks single nodes only in columns that touch a solid.
  std::vector<std::uint8_t> column_solid_;
  /// The same, 1 if every node of the column is solid (a pillar's column).
  std::vector<std::uint8_t> column_all_solid_;
  /// Per (j0, i0) of the interior x range, j0 + W rows wrapped in y: 1 if any of the W x W
  /// columns from (i0, j0) touches a solid (index j0 * nx + i0; W = the kernel's width).
  std::vector<std::uint8_t> block_solid_;
  // Spreading's grouping, kept between calls: groups 0..T-1 are the markers inside x slab t,
  // groups T..2T-1 those whose support straddles the slab's lower edge (slab 0: the x face).
  mutable std::vector<std::uint32_t> order_;
  mutable std::vector<std::uint32_t> group_start_;
  mutable std::vector<std::uint8_t> group_of_;
  mutable std::vector<std::uint32_t> by_column_, bin_, bin_start_;
  mutable std::vector<int> first_;
  // The 4-point footprints of the last spread, in order_; interpolation at the same positions
  // (a coupled step spreads and interpolates at one set) reads them instead of recomputing.
  // Those across the shifted x face (about a tenth of a dense run's markers) are kept too.
  // Those by the pillar keep their masked footprints, and the rest near a solid their stencil()
  // nodes and weights, packed per spreading thread.
  enum : std::uint8_t { kKeptNone, kKeptSeparable, kKeptSplit, kKeptStencil, kKeptMasked };
  mutable std::vector<IbFootprint<4>> spread_footprints_;
  mutable std::vector<IbSplitFootprint<4>> spread_split_;
  mutable std::vector<KeptStencil> spread_stencil_;
  mutable std::vector<std::vector<std::size_t>> kept_nodes_;
  mutable std::vector<std::vector<double>> kept_weights_;
  mutable std::vector<std::vector<IbMaskedFootprint<4>>> kept_masked_;
  mutable std::vector<std::uint8_t> spread_kind_;
  mutable std::vector<double> spread_positions_;
  mutable bool spread_done_ = false;  // spread_positions_ holds a spread's positions
};

}  // namespace dld::fluid
