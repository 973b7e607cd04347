// SPDX-License-Identifier: MIT
// The lattice-Boltzmann fluid of one box: populations, boundaries, forcing, lateral control.
// One step: fill periodic ghosts -> bounce-back links -> fused stream + collide -> controller.
// Lattice units throughout.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "fluid/bounce_back.hpp"
#include "fluid/collision.hpp"
#include "fluid/huge_page_allocator.hpp"
#include "fluid/lateral_controller.hpp"
#include "fluid/lattice.hpp"
#include "fluid/population_view.hpp"
#include "fluid/relaxation_field.hpp"
#include "fluid/stream_collide.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

struct FluidConfig {
  Domain domain;
  CollisionKind collision = CollisionKind::kTrt;
  double tau = 1.0;           ///< outer relaxation time
  double magic = 3.0 / 16.0;  ///< TRT Lambda
  double force_x = 0.0;       ///< uniform body force density along x
  double force_y = 0.0;       ///< initial y force (adjusted if lateral_control)
  bool lateral_control = false;
  double rho0 = 1.0;  ///< initial density
  /// Back the per-node arrays with huge pages (fluid/huge_page_allocator.hpp).
  bool huge_pages = true;
  /// One population array updated in place (the AA pattern, fluid/population_view.hpp) instead
  /// of pulling from one array into another: the same arithmetic, a third less memory traffic.
  bool in_place = true;
};

/// The fluid configuration a scene asks for (the DLD unit cell).
FluidConfig fluid_config(const Scene& scene);

class FluidSolver {
 public:
  explicit FluidSolver(const FluidConfig& config);

  void step();
  std::int64_t steps() const { return steps_; }
  const Lattice& lattice() const { return lattice_; }
  const FluidConfig& config() const { return config_; }

  /// Totals of the last update (mass and momentum including the half-force shift).
  const FlowSums& sums() const { return sums_; }
  /// Box means over fluid nodes: u = total momentum / total mass.
  std::array<double, 3> mean_velocity() const;
  double total_mass() const { return sums_.mass; }
  double force_y() const { return force_y_; }

  /// Density and velocity of node (i, j, k) from the current populations.
  Moments node_moments(int i, int j, int k) const;
  /// Fields over the interior, x fastest (index (k * ny + j) * nx + i); solid nodes hold 0 velocity
  /// and density rho0.
  void fields(std::vector<double>& rho, std::vector<double>& ux, std::vector<double>& uy,
              std::vector<double>& uz) const;

  /// Velocity of every fluid node (0 on solid nodes) as three arrays of padded size, from the
  /// current populations. With a force field the step's kernel stored it already (no extra pass);
  /// otherwise it is recomputed on each call.
  std::array<const double*, 3> velocity_field();

  /// Per-node body force field, added to the uniform force (created zeroed on first call).
  std::array<double*, 3> force_field();
  /// Per-node relaxation times and their rates (created with tau everywhere on first call).
  RelaxationField& relaxation_field();

  /// Everything a restart needs besides the populations (checkpoints, fluid/checkpoint.hpp).
  struct Memory {
    std::int64_t steps = 0;
    double force_y = 0, applied_force_y = 0, controller_integral = 0;
    FlowSums sums;
  };
  Memory memory() const;
  /// Restores a checkpoint: populations (padded SoA, as populations()) and memory.
  void restore(const std::vector<double>& populations, const Memory& m);

  /// The post-collision populations in the pull layout (SoA, stride lattice().padded_size()):
  /// exact at fluid nodes; the other slots are refilled before a step reads them.
  std::vector<double> pull_populations() const;
  /// The populations for writing, in the pull layout (converted first if updated in place).
  double* populations() {
    velocity_current_ = false;  // the caller may change them
    to_pull_layout();
    return f_.data();
  }

 private:
  FluidConfig config_;
  Lattice lattice_;
  using Field = std::vector<double, HugePageAllocator<double>>;
  Field f_, g_;  ///< current and next populations
  Field force_field_, velocity_;
  std::unique_ptr<RelaxationField> relaxation_;
  bool velocity_current_ = false;  ///< velocity_ holds the kernel's u of the last step
  FlowSums sums_;
  double force_y_ = 0.0;          ///< y force for the next step
  double applied_force_y_ = 0.0;  ///< y force of the last step (to recover u)
  std::unique_ptr<LateralController> controller_;
  std::int64_t steps_ = 0;
  PopulationLayout layout_ = PopulationLayout::kPull;  ///< where f_ keeps post(q, x)
  std::unique_ptr<BounceBackTables> swapped_links_, shifted_links_;

  /// The in-place update's layouts (fluid/population_layout.cpp).
  void relabel_pull_as_swapped();
  void to_pull_layout();
  const BounceBackTables& bounce_back_tables(PopulationLayout layout);
};

}  // namespace dld::fluid
