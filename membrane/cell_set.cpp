// SPDX-License-Identifier: MIT
#include "membrane/cell_set.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shared/input_error.hpp"

namespace dld::membrane {

CellSet::CellSet(TriMesh reference, MembraneMechanics mechanics, std::optional<Contact> contact)
    : reference_(std::move(reference)),
      mechanics_(std::move(mechanics)),
      contact_(std::move(contact)) {
  reference_.nodes.colwise() -= membrane::centroid(reference_.nodes);
  x_.resize(3, 0);
}

void CellSet::add_cell(const Eigen::Vector3d& centre, double angle_rad) {
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Points p = (rot * reference_.nodes).colwise() + centre;
  add_cell(p);
}

void CellSet::add_cell(const Points& nodes) {
  if (nodes.cols() != nodes_per_cell())
    throw InputError(fmt::format("cell has {} nodes, the reference mesh has {}", nodes.cols(),
                                 nodes_per_cell()));
  if (!nodes.allFinite()) throw InputError("cell node positions must be finite");
  x_.conservativeResize(3, x_.cols() + nodes.cols());
  x_.rightCols(nodes.cols()) = nodes;
  ++cells_;
}

double CellSet::compute_forces(Points& f) const {
  f.setZero(3, x_.cols());
  double e = 0.0;
  const int n = nodes_per_cell();
  // Cells in parallel; each writes only its own columns of f.
#pragma omp parallel for reduction(+ : e) schedule(dynamic) if (cells_ > 1)
  for (int k = 0; k < cells_; ++k)
    e += mechanics_.add_forces(cell_positions(k), f.middleCols(Eigen::Index{k} * n, n));
  if (contact_) e += contact_->add_forces(x_, n, f, &ghosts_);
  return e;
}

double CellSet::energy() const {
  double e = 0.0;
  for (int k = 0; k < cells_; ++k) e += mechanics_.energy(cell_positions(k));
  if (contact_) e += contact_->energy(x_, nodes_per_cell(), &ghosts_);
  return e;
}

void CellSet::move(const Points& velocity, double dt) {
  if (velocity.cols() != x_.cols())
    throw InputError(
        fmt::format("velocity field has {} nodes, the cells have {}", velocity.cols(), x_.cols()));
  x_ += dt * velocity;
}

void CellSet::move(std::span<const double> velocity, double dt) {
  if (velocity.size() != static_cast<std::size_t>(x_.size()))
    throw InputError(fmt::format("velocity array has {} values, the cells need {} (3 per node)",
                                 velocity.size(), x_.size()));
  x_ += dt * Eigen::Map<const Points>(velocity.data(), 3, x_.cols());
}

Eigen::Vector3d CellSet::centroid(int k) const {
  return cell_positions(k).rowwise().mean();
}

double CellSet::volume(int k) const {
  return enclosed_volume(reference_, cell_positions(k));
}

double CellSet::area(int k) const {
  return surface_area(reference_, cell_positions(k));
}

}  // namespace dld::membrane
