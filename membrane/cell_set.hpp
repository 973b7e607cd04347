// SPDX-License-Identifier: MIT
// The cells a membrane process owns: one reference mesh and one set of models shared by all
// cells, node positions of all cells in one matrix (cell k holds columns [k n, (k+1) n)),
// optional contact. This is the API the coupler drives each step:
//   positions() -> X,  compute_forces(F),  move(U, dt): X += U dt.
#pragma once
#include <optional>
#include <span>

#include "membrane/contact.hpp"
#include "membrane/mesh.hpp"
#include "membrane/model_registry.hpp"

namespace dld::membrane {

class CellSet {
 public:
  CellSet(TriMesh reference, MembraneMechanics mechanics,
          std::optional<Contact> contact = std::nullopt);

  /// Adds a cell in its rest shape: reference centred at `centre`, turned by `angle_rad` about z
  /// (the reference's axis of symmetry is z, so the cell lies flat).
  void add_cell(const Eigen::Vector3d& centre, double angle_rad = 0.0);
  /// Adds a cell with given node positions (e.g. from a checkpoint); throws InputError on a
  /// wrong node count or non-finite values.
  void add_cell(const Points& nodes);

  int cell_count() const { return cells_; }
  int nodes_per_cell() const { return reference_.node_count(); }
  int node_count() const { return static_cast<int>(x_.cols()); }
  const TriMesh& reference() const { return reference_; }
  const MembraneMechanics& mechanics() const { return mechanics_; }
  const std::optional<Contact>& contact() const { return contact_; }

  /// All node positions [lattice lengths]; unwrapped (a cell stays in one piece across the box).
  const Points& positions() const { return x_; }
  Points& positions() { return x_; }
  auto cell_positions(int k) const {
    return x_.middleCols(Eigen::Index{k} * nodes_per_cell(), nodes_per_cell());
  }

  /// Other processes' cells near these (their nodes at the positions of the next
  /// compute_forces), for the contact; none when this process holds every cell.
  void set_ghosts(ContactGhosts ghosts) { ghosts_ = std::move(ghosts); }
  const ContactGhosts& ghosts() const { return ghosts_; }

  /// Membrane plus contact forces on every node [lattice force]; f is resized. Returns the total
  /// energy [lattice energy].
  double compute_forces(Points& f) const;
  double energy() const;
  /// X += U dt (no-slip: nodes move with the interpolated fluid velocity).
  void move(const Points& velocity, double dt);
  /// The same with U as node-major x, y, z doubles (the coupler's frame layout).
  void move(std::span<const double> velocity, double dt);
  /// Positions as node-major x, y, z doubles, cells in order (the coupler's frame layout; a view
  /// valid until cells are added).
  std::span<const double> flat_positions() const {
    return {x_.data(), static_cast<std::size_t>(x_.size())};
  }

  Eigen::Vector3d centroid(int k) const;
  double volume(int k) const;
  double area(int k) const;

 private:
  TriMesh reference_;  // rest shape centred at the origin
  MembraneMechanics mechanics_;
  std::optional<Contact> contact_;
  Points x_;
  int cells_ = 0;
  ContactGhosts ghosts_;
};

}  // namespace dld::membrane
