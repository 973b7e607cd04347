// SPDX-License-Identifier: MIT
#include "fluid/fluid_solver.hpp"

#include <stdexcept>

#include "fluid/bounce_back.hpp"
#include "fluid/collision_registry.hpp"
#include "fluid/periodic_ghosts.hpp"

namespace dld::fluid {

FluidConfig fluid_config(const Scene& scene) {
  FluidConfig c;
  c.domain = dld_domain(scene.cell_lu(), scene.nx(), scene.ny(), scene.nz());
  c.domain.curved_walls = scene.lattice.curved_walls;
  c.collision = scene.lattice.collision;
  c.tau = scene.lattice.tau;
  c.magic = scene.lattice.trt_magic;
  c.force_x = scene.force_x_lu();
  c.lateral_control = scene.drive.lateral_control;
  return c;
}

FluidSolver::FluidSolver(const FluidConfig& config)
    : config_(config),
      lattice_(config.domain),
      f_(HugePageAllocator<double>(config.huge_pages)),
      g_(HugePageAllocator<double>(config.huge_pages)),
      force_field_(HugePageAllocator<double>(config.huge_pages)),
      velocity_(HugePageAllocator<double>(config.huge_pages)),
      force_y_(config.force_y) {
  const std::size_t n = lattice_.padded_size();
  f_.assign(n * D3Q19::q + kPopulationPadding, 0.0);
  for (int i = 0; i < D3Q19::q; ++i)
    for (std::size_t s = 0; s < n; ++s)
      if (!lattice_.solid_mask()[s]) f_[i * n + s] = D3Q19::w[i] * config.rho0;
  if (!config.in_place) g_ = f_;  // the pull update's second array
  if (config.lateral_control) {
    const double h = config.domain.walls_z ? config.domain.nz : config.domain.ny;
    controller_ = std::make_unique<LateralController>(h, (config.tau - 0.5) / 3.0);
    controller_->set_force(config.force_y);
  }
  sums_.mass = config.rho0 * static_cast<double>(lattice_.fluid_nodes());
}

std::array<double*, 3> FluidSolver::force_field() {
  const std::size_t n = lattice_.padded_size();
  if (force_field_.empty()) force_field_.assign(3 * n, 0.0);
  return {force_field_.data(), force_field_.data() + n, force_field_.data() + 2 * n};
}

RelaxationField& FluidSolver::relaxation_field() {
  if (!relaxation_) {
    const RelaxationField::RatesOf rates = rates_function(config_.collision);
    relaxation_ = std::make_unique<RelaxationField>(lattice_.padded_size(), config_.tau, rates,
                                                    config_.magic, config_.huge_pages);
  }
  return *relaxation_;
}

namespace {
template <typename C>
FlowSums dispatch_fields(bool ff, bool tf, const Lattice& L, const PopulationView& in,
                         const PopulationView& out, const KernelParams& p) {
  if (ff && tf) return stream_collide<C, true, true>(L, in, out, p);
  if (ff) return stream_collide<C, true, false>(L, in, out, p);
  if (tf) return stream_collide<C, false, true>(L, in, out, p);
  return stream_collide<C, false, false>(L, in, out, p);
}
}  // namespace

void FluidSolver::step() {
  // Pull: from f_ to g_. In place: f_ alternates between the swapped and the shifted layout
  // (fluid/population_view.hpp); the first step relabels the initial pull layout as swapped.
  if (config_.in_place && layout_ == PopulationLayout::kPull) relabel_pull_as_swapped();
  const PopulationView in(lattice_, f_.data(), layout_);
  const PopulationLayout next = !config_.in_place ? PopulationLayout::kPull
                                : layout_ == PopulationLayout::kSwapped
                                    ? PopulationLayout::kShifted
                                    : PopulationLayout::kSwapped;
  const PopulationView out(lattice_, config_.in_place ? f_.data() : g_.data(), next);
  fill_periodic_ghosts(lattice_, in);
  if (config_.in_place) {
    const BounceBackTables& t = bounce_back_tables(layout_);
    apply_bounce_back(lattice_, t.links, t.curved, in, f_.data());
  } else {
    apply_bounce_back(lattice_, f_.data());
  }

  KernelParams p;
  p.tau = config_.tau;
  p.magic = config_.magic;
  p.force[0] = config_.force_x;
  p.force[1] = force_y_;
  const bool ff = !force_field_.empty(), tf = relaxation_ != nullptr;
  if (ff) {
    const std::size_t n = lattice_.padded_size();
    if (velocity_.empty()) velocity_.assign(3 * n, 0.0);
    for (int a = 0; a < 3; ++a) {
      p.force_field[a] = force_field_.data() + a * n;
      p.velocity[a] = velocity_.data() + a * n;
    }
  }
  if (tf) {
    p.rate_plus = relaxation_->plus();
    p.rate_minus = relaxation_->minus();
  }
  sums_ = with_collision(config_.collision, [&]<typename C>() {
    return dispatch_fields<C>(ff, tf, lattice_, in, out, p);
  });
  applied_force_y_ = force_y_;
  if (config_.in_place) {
    layout_ = next;
  } else {
    f_.swap(g_);
  }
  velocity_current_ = ff;
  ++steps_;
  if (controller_) force_y_ = controller_->update(mean_velocity()[1]);
}

FluidSolver::Memory FluidSolver::memory() const {
  return {steps_, force_y_, applied_force_y_, controller_ ? controller_->integral() : 0.0, sums_};
}

void FluidSolver::restore(const std::vector<double>& populations, const Memory& m) {
  if (populations.size() != f_.size())
    throw std::invalid_argument(
        "FluidSolver::restore: population count does not match the lattice");
  f_.assign(populations.begin(), populations.end());
  layout_ = PopulationLayout::kPull;
  steps_ = m.steps;
  force_y_ = m.force_y;
  applied_force_y_ = m.applied_force_y;
  if (controller_) controller_->restore(m.controller_integral, m.force_y);
  sums_ = m.sums;
  velocity_current_ = false;
}

std::array<double, 3> FluidSolver::mean_velocity() const {
  return {sums_.momentum_x / sums_.mass, sums_.momentum_y / sums_.mass,
          sums_.momentum_z / sums_.mass};
}

Moments FluidSolver::node_moments(int i, int j, int k) const {
  // Post-collision populations carry momentum rho u + F/2 (Guo): remove the half force again.
  const std::size_t n = lattice_.padded_size();
  const std::size_t s = lattice_.index(i, j, k);
  double fx = config_.force_x, fy = applied_force_y_, fz = 0.0;
  if (!force_field_.empty()) {
    fx += force_field_[s];
    fy += force_field_[n + s];
    fz += force_field_[2 * n + s];
  }
  const PopulationView post(lattice_, const_cast<double*>(f_.data()), layout_);
  double rho = 0, jx = 0, jy = 0, jz = 0;
  for (int q = 0; q < D3Q19::q; ++q) {
    const double v = post(q, s);
    rho += v;
    jx += v * D3Q19::c[q][0];
    jy += v * D3Q19::c[q][1];
    jz += v * D3Q19::c[q][2];
  }
  return {rho, (jx - 0.5 * fx) / rho, (jy - 0.5 * fy) / rho, (jz - 0.5 * fz) / rho};
}

std::array<const double*, 3> FluidSolver::velocity_field() {
  const std::size_t n = lattice_.padded_size();
  if (velocity_.empty()) velocity_.assign(3 * n, 0.0);
  if (velocity_current_) return {velocity_.data(), velocity_.data() + n, velocity_.data() + 2 * n};
  const int nx = lattice_.nx(), ny = lattice_.ny(), nz = lattice_.nz();
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (lattice_.solid(i, j, k)) continue;
        const Moments m = node_moments(i, j, k);
        const std::size_t s = lattice_.index(i, j, k);
        velocity_[s] = m.ux;
        velocity_[n + s] = m.uy;
        velocity_[2 * n + s] = m.uz;
      }
  return {velocity_.data(), velocity_.data() + n, velocity_.data() + 2 * n};
}

void FluidSolver::fields(std::vector<double>& rho, std::vector<double>& ux, std::vector<double>& uy,
                         std::vector<double>& uz) const {
  const int nx = lattice_.nx(), ny = lattice_.ny(), nz = lattice_.nz();
  const std::size_t total = static_cast<std::size_t>(nx) * ny * nz;
  rho.assign(total, config_.rho0);
  ux.assign(total, 0.0);
  uy.assign(total, 0.0);
  uz.assign(total, 0.0);
#pragma omp parallel for schedule(static)
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        if (lattice_.solid(i, j, k)) continue;
        const std::size_t o = (static_cast<std::size_t>(k) * ny + j) * nx + i;
        const Moments m = node_moments(i, j, k);
        rho[o] = m.rho;
        ux[o] = m.ux;
        uy[o] = m.uy;
        uz[o] = m.uz;
      }
}

}  // namespace dld::fluid
