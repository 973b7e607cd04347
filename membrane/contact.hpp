// SPDX-License-Identifier: MIT
// Short-range repulsion that keeps a thin fluid layer between a membrane node and the z walls,
// the pillar, and the nodes of other cells (SPEC section 4). Pair potential with cut-off r_c:
//   phi(s) = eps (r_c - s)^2 / (s r_c),  force magnitude eps (r_c^2 - s^2) / (r_c s^2),
// zero with zero slope at r_c and diverging as 1/s^2; below s_min = 0.05 r_c it continues
// linearly so that an overlapped node gets a large finite push instead of a blow-up.
// Cell-cell pairs come from a cell list over the box with ghost images, honouring periodic y and
// shifted-periodic x (leaving at x = lambda at height y re-enters at x = 0 at y - d).
#pragma once
#include <vector>

#include "membrane/mesh.hpp"
#include "shared/dld_geometry.hpp"

namespace dld::membrane {

struct ContactParams {
  double range = 1.0;     ///< cut-off r_c [lattice lengths]
  double strength = 0.0;  ///< eps [lattice energy]
  bool walls = true;      ///< z walls at z = 0 and z = box.depth
  bool pillar = true;     ///< the pillar of box (nearest images)
  bool cells = true;      ///< nodes of different cells
};

/// Pair potential value and force magnitude (-dphi/ds) at separation s.
struct ContactLaw {
  double rc, eps;
  double energy(double s) const;
  double force(double s) const;
};

class Contact {
 public:
  /// box in lattice units. Throws InputError for a non-positive range, negative strength, or a
  /// range larger than a quarter of the box.
  Contact(const DldCell& box_lu, const ContactParams& p);

  /// Adds contact forces for all nodes; x holds the cells one after another,
  /// `nodes_per_cell` nodes each (positions may be unwrapped). Returns the contact energy.
  double add_forces(const Points& x, int nodes_per_cell, Points& f) const;
  double energy(const Points& x, int nodes_per_cell) const;
  /// Number of cell-cell node pairs within range at the last add_forces (each pair once).
  long last_pair_count() const { return pairs_; }

  const ContactParams& params() const { return p_; }

 private:
  double evaluate(const Points& x, int nodes_per_cell, Points* f) const;
  void build_images(const Points& x, int nodes_per_cell) const;

  DldCell box_;
  ContactParams p_;
  ContactLaw law_;
  // Cell-list scratch, rebuilt at every call.
  mutable std::vector<Eigen::Vector3d> wrapped_;  // real node positions folded into the box
  mutable std::vector<Eigen::Vector3d> image_pos_;
  mutable std::vector<int> image_node_;
  struct Image {
    double x, y, z;
    int cell;
  };
  mutable std::vector<Image> sorted_;  // images in bin order, so a row of bins is one range
  mutable std::vector<int> bin_start_;
  mutable int nbx_ = 0, nby_ = 0, nbz_ = 0;
  mutable double z0_ = 0.0, bin_ = 1.0;
  mutable long pairs_ = 0;
};

}  // namespace dld::membrane
