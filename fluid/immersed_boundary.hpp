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

#include "fluid/ib_kernel.hpp"
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

 private:
  const Lattice& lattice_;
  IbKernel kernel_;
  /// Per (i, j) column of the padded x-y plane (index (j + 1) * px + i + 1): 1 if any node of the
  /// column is solid, so stencil() checks single nodes only in columns that touch a solid.
  std::vector<std::uint8_t> column_solid_;
  mutable std::vector<double> scratch_;  ///< per-thread force fields of spread()
};

}  // namespace dld::fluid
