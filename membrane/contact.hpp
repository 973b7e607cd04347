// SPDX-License-Identifier: MIT
// Short-range repulsion that keeps a thin fluid layer between a membrane node and the z walls,
// the pillar, and the nodes of other cells (SPEC section 4). Pair potential with cut-off r_c:
//   phi(s) = eps (r_c - s)^2 / (s r_c),  force magnitude eps (r_c^2 - s^2) / (r_c s^2),
// zero with zero slope at r_c and diverging as 1/s^2; below s_min = 0.05 r_c it continues
// linearly so that an overlapped node gets a large finite push instead of a blow-up.
// Cell-cell pairs come from a cell list over the box with ghost images, honouring periodic y and
// shifted-periodic x (leaving at x = lambda at height y re-enters at x = 0 at y - d), kept as a
// neighbour list of pairs within r_c + skin (Verlet) and rebuilt only when some node has moved more
// than skin / 2 since the last build, so every pair within r_c is always in it. Each node's list is
// sorted, so the forces do not depend on the step at which the list was built (a resumed run gives
// the same numbers as an uninterrupted one).
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

/// Other processes' cells the contact of this process must see (coupler/halo.hpp): their nodes
/// push this process's nodes and get nothing back here (their own process computes that side).
/// Pairs are ordered by global node index, so a node's force sums its pairs in the same order
/// whatever the split of the cells over processes.
struct ContactGhosts {
  int first_cell = 0;      ///< global index of this process's first cell
  std::vector<int> cells;  ///< global indices of the ghost cells, ascending
  Points x;                ///< their nodes (nodes_per_cell each), cells in that order, unwrapped
};

class Contact {
 public:
  /// box in lattice units. Throws InputError for a non-positive range, negative strength, or a
  /// range larger than a quarter of the box.
  Contact(const DldCell& box_lu, const ContactParams& p);

  /// Adds contact forces for all nodes; x holds the cells one after another,
  /// `nodes_per_cell` nodes each (positions may be unwrapped), and `ghosts` other processes'
  /// cells near them (none: x is every cell). Returns the contact energy of x's nodes (a pair
  /// with a ghost counts half: its other half belongs to the ghost's process).
  double add_forces(const Points& x, int nodes_per_cell, Points& f,
                    const ContactGhosts* ghosts = nullptr) const;
  double energy(const Points& x, int nodes_per_cell, const ContactGhosts* ghosts = nullptr) const;
  /// Number of cell-cell node pairs within range at the last add_forces (each pair once), and
  /// how many of them had a ghost node.
  long last_pair_count() const { return pairs_; }
  long last_ghost_pair_count() const { return ghost_pairs_; }
  /// How near another process's cell must come for its nodes to be needed: the cut-off plus
  /// the neighbour list's skin [lattice lengths].
  double halo_width() const { return p_.range + skin_; }

  const ContactParams& params() const { return p_; }

 private:
  double evaluate(const Points& x, int nodes_per_cell, Points* f,
                  const ContactGhosts* ghosts) const;
  /// The nodes the contact sees (x, then the ghosts' nodes) and each one's global cell index.
  const Points& gather(const Points& x, int nodes_per_cell, const ContactGhosts* ghosts) const;
  /// Folds every node into the box (walls and pillar act on folded positions).
  void wrap_nodes(const Points& x) const;
  /// Images of the folded nodes within `cutoff` of a periodic face, binned by cells of side
  /// >= cutoff.
  void build_images(int nodes_per_cell, double cutoff) const;
  /// The neighbour list: for each node, the nodes of other cells (with the periodic translation
  /// of their image) within r_c + skin.
  void build_pairs(const Points& x, int nodes_per_cell, int own_nodes) const;
  bool pairs_stale(const Points& x, int nodes_per_cell) const;

  DldCell box_;
  ContactParams p_;
  ContactLaw law_;
  // Cell-list scratch, rebuilt at every call.
  mutable std::vector<Eigen::Vector3d> wrapped_;  // real node positions folded into the box
  mutable std::vector<Eigen::Vector3d> image_pos_;
  mutable std::vector<int> image_node_;
  struct Image {
    double x, y, z;
    int cell, node;
  };
  struct Neighbour {
    int node;
    Eigen::Vector3d shift;  ///< x_i - (x_node + shift) is the pair's separation (unwrapped x)
  };
  double skin_ = 0.0;
  mutable std::vector<int> pair_start_;  // node i's neighbours: pairs_[pair_start_[i] .. [i + 1])
  mutable std::vector<Neighbour> pairs_list_;
  mutable Points x_built_;                          // node positions at the last build
  mutable std::vector<int> cell_of_, cells_built_;  // global cell of each local cell (now, build)
  mutable Points with_ghosts_;                      // x and the ghosts' nodes
  mutable int built_nodes_per_cell_ = 0;
  mutable std::vector<Image> sorted_;  // images in bin order, so a row of bins is one range
  mutable std::vector<int> bin_start_;
  mutable int nbx_ = 0, nby_ = 0, nbz_ = 0;
  mutable double z0_ = 0.0, bin_ = 1.0;
  mutable long pairs_ = 0, ghost_pairs_ = 0;
};

}  // namespace dld::membrane
