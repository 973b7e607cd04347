// SPDX-License-Identifier: MIT
// Lattice topology: padded structure-of-arrays indexing (one ghost layer on each side), the fluid
// runs along x that the kernel sweeps, and the bounce-back links.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fluid/d3q19.hpp"
#include "fluid/domain.hpp"

namespace dld::fluid {

/// A run of consecutive fluid nodes along x: padded index of the first node and its length.
struct Segment {
  std::size_t begin;
  int length;
};

/// Half-way bounce-back link: before streaming, the ghost/solid slot `target` (population i of
/// a solid node s) receives the post-collision population opp(i) of the fluid node s + c_i,
/// so that the pull of s + c_i in direction i reads its own reflected population.
struct BounceBackLink {
  std::uint32_t target;  ///< i * padded_size + s
  std::uint32_t source;  ///< opp(i) * padded_size + (s + c_i)
};

/// Interpolated bounce-back link (Bouzidi, Firdaouss, Lallemand, Phys. Fluids 13 (2001) 3452,
/// eq. 5): target = a * f[first] + b * f[second], with the wall at fraction t of the link.
struct CurvedLink {
  std::uint32_t target;
  std::uint32_t first;   ///< opp(i) * n + f: the population that hits the wall
  std::uint32_t second;  ///< t < 1/2: opp(i) * n + (f + c_i), the node behind; else i * n + f
  double a, b;
};

class Lattice {
 public:
  explicit Lattice(Domain domain);

  const Domain& domain() const { return domain_; }
  int nx() const { return domain_.nx; }
  int ny() const { return domain_.ny; }
  int nz() const { return domain_.nz; }
  int px() const { return domain_.nx + 2; }
  int py() const { return domain_.ny + 2; }
  int pz() const { return domain_.nz + 2; }
  /// Number of padded nodes: the stride between two populations in the SoA arrays.
  std::size_t padded_size() const { return padded_; }
  /// Padded index of node (i, j, k); i in [-1, nx], j in [-1, ny], k in [-1, nz].
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k + 1) * py() + static_cast<std::size_t>(j + 1)) * px() +
           static_cast<std::size_t>(i + 1);
  }
  /// Padded-index offset of the neighbour along c_i.
  std::ptrdiff_t offset(int i) const { return offsets_[i]; }
  bool solid(int i, int j, int k) const { return solid_[index(i, j, k)] != 0; }
  const std::vector<std::uint8_t>& solid_mask() const { return solid_; }
  const std::vector<Segment>& segments() const { return segments_; }
  /// Links to solid nodes inside the box (pillars); the z walls are whole planes instead.
  const std::vector<BounceBackLink>& links() const { return links_; }
  /// Pillar links with the wall at its true position (Domain::curved_walls).
  const std::vector<CurvedLink>& curved_links() const { return curved_links_; }
  std::size_t fluid_nodes() const { return fluid_nodes_; }

 private:
  Domain domain_;
  std::size_t padded_ = 0;
  std::array<std::ptrdiff_t, D3Q19::q> offsets_{};
  std::vector<std::uint8_t> solid_;
  std::vector<Segment> segments_;
  std::vector<BounceBackLink> links_;
  std::vector<CurvedLink> curved_links_;
  std::size_t fluid_nodes_ = 0;
};

}  // namespace dld::fluid
