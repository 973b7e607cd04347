// SPDX-License-Identifier: MIT
// The coupled mode of dld-fluid: serve membrane programs over the coupler. Each step: receive
// marker positions and forces, spread the forces (immersed boundary), advance the lattice,
// interpolate the velocity at the markers, send it back (DESIGN.md, "The shape").
// Markers are in lattice units; the fluid folds them into its box through the shifted faces.
#include "fluid/coupled_main.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/fluid_side.hpp"
#include "coupler/scene_identity.hpp"
#include "fluid/checkpoint.hpp"
#include "fluid/fluid_output.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/immersed_boundary.hpp"
#include "fluid/observables.hpp"
#include "fluid/viscosity_contrast.hpp"

namespace dld::fluid {

namespace {

/// Stops the run when the lattice is no longer finite (its mass or momentum after the step):
/// nothing after it may reach a checkpoint or the membranes.
void require_finite_lattice(const FluidSolver& solver) {
  const FlowSums& s = solver.sums();
  if (!std::isfinite(s.mass + s.momentum_x + s.momentum_y + s.momentum_z)) {
    throw std::runtime_error(fmt::format(
        "fluid: the lattice is not finite after step {} (mass {}, momentum x {}); no checkpoint "
        "written after the last one",
        solver.steps(), s.mass, s.momentum_x));
  }
}

/// Speeds far beyond the lattice's (|u| of a few 0.01 at most in a valid run; the speed of sound
/// is 0.577) come only from forces the lattice cannot take: stop, naming the marker's peer.
constexpr double kMaxMarkerSpeedLu = 0.2;

void require_resolved_velocities(std::span<const double> u, const coupler::FluidSide& side,
                                 std::int64_t step) {
  double worst = 0.0;
  std::size_t at = 0;
  for (std::size_t m = 0; 3 * m < u.size(); ++m) {
    const double s2 =
        u[3 * m] * u[3 * m] + u[3 * m + 1] * u[3 * m + 1] + u[3 * m + 2] * u[3 * m + 2];
    if (!(s2 <= worst)) {  // NaN counts as the worst
      worst = s2, at = m;
      if (!std::isfinite(s2)) break;
    }
  }
  if (std::isfinite(worst) && worst <= kMaxMarkerSpeedLu * kMaxMarkerSpeedLu) return;
  std::size_t peer = 0;
  while (peer + 1 < side.peer_count() && side.node_offset(peer + 1) <= at) ++peer;
  throw std::runtime_error(fmt::format(
      "fluid: velocity {:.3g} lattice units at node {} of {} after step {} (limit {}): the "
      "lattice cannot take the forces it sent",
      std::sqrt(worst), at - side.node_offset(peer), side.peer_label(peer), step,
      kMaxMarkerSpeedLu));
}

}  // namespace

namespace {
// Last resort if a membrane peer's shared memory loses pages in the middle of a step (the size is
// checked before each use, coupler/shared_segment.hpp): a message and an exit code, not a bare
// SIGBUS; nothing is checkpointed after it.
void on_sigbus(int) {
  static const char kMessage[] =
      "[dld-fluid] error: a membrane peer's shared memory lost pages during a step (SIGBUS); no "
      "checkpoint written after the last one\n";
  (void)!write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  _exit(4);
}

// Ctrl-C (or dld-run passing one on) ends the run after the current step: the fluid tells every
// membrane program to stop at the same step, so their files end together.
volatile sig_atomic_t g_stop = 0;
void on_sigint(int) {
  g_stop = 1;
}
}  // namespace

namespace {

/// The inside/outside viscosity field, built only when the scene asks for one (ratio 1 costs
/// nothing).
std::unique_ptr<ViscosityContrast> make_contrast(const Scene& scene, const FluidSolver& solver,
                                                 const coupler::FluidSide& side) {
  if (scene.fluid.viscosity_ratio == 1.0) return nullptr;
  std::unique_ptr<ViscosityContrast> contrast;
  try {
    contrast =
        std::make_unique<ViscosityContrast>(solver.lattice(), scene.lattice.tau, scene.tau_inner(),
                                            side.cell_nodes(), side.cell_faces(), side.faces());
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(fmt::format("scene {}: [fluid] viscosity_ratio = {}: {}", scene.file,
                                         scene.fluid.viscosity_ratio, e.what()));
  }
  spdlog::info("viscosity contrast {}: tau {} outside, {:.6g} inside the cells",
               scene.fluid.viscosity_ratio, scene.lattice.tau, scene.tau_inner());
  return contrast;
}

/// Rebuilds the viscosity field at the markers x on the steps [coupling] viscosity_field_every
/// names (time-scale separation: held in between) and on the run's first step.
void update_contrast(ViscosityContrast& contrast, const Scene& scene, FluidSolver& solver,
                     std::span<const double> x, bool first, bool& warned_unpaired) {
  if (!first && solver.steps() % scene.coupling.viscosity_field_every != 0) return;
  contrast.update(x, solver.relaxation_field());
  if (first) {
    spdlog::info("viscosity contrast: {} nodes inside the cells at step {}",
                 contrast.inside_nodes().size(), solver.steps());
  }
  if (contrast.unpaired_columns() > 0 && !warned_unpaired) {
    spdlog::warn(
        "viscosity contrast at step {}: {} lattice columns cross a membrane an odd number of times "
        "(open or self-intersecting surface?); their inside is a guess",
        solver.steps(), contrast.unpaired_columns());
    warned_unpaired = true;
  }
}

/// Wall time per phase of a coupled step: waiting for the membranes (their work plus the
/// exchange), spreading, the inside/outside viscosity field, the lattice step, interpolating and
/// sending.
struct PhaseTimes {
  using Clock = std::chrono::steady_clock;
  double wait = 0, spread = 0, contrast = 0, fluid = 0, interpolate = 0;
  Clock::time_point t0 = Clock::now();
  void lap(double& phase) {
    const auto t1 = Clock::now();
    phase += std::chrono::duration<double>(t1 - t0).count();
    t0 = t1;
  }
  void report(std::int64_t steps) const {
    if (steps <= 0) return;
    const double ms = 1e3 / static_cast<double>(steps);
    spdlog::info(
        "time per step [ms]: fluid {:.3f}, spread {:.3f}, viscosity field {:.3f}, "
        "interpolate+send {:.3f}, waiting for the membranes {:.3f}",
        fluid * ms, spread * ms, contrast * ms, interpolate * ms, wait * ms);
  }
};

/// The progress line and the run file's sample, every [run] log_every steps.
void log_progress(const Scene& scene, const FluidSolver& solver, FluidRunFile* out,
                  std::int64_t steps, std::chrono::steady_clock::time_point start) {
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto u = solver.mean_velocity();
  if (out) out->sample(solver, gap_profile(solver, scene.cell_lu()).flux);
  spdlog::info("step {:>8}  <u_x> {:.5g} m/s  {:.1f} steps/s", solver.steps(),
               scene.units().velocity_m_s(u[0]), steps / secs);
  if (!std::isfinite(u[0])) {
    throw std::runtime_error(
        fmt::format("fluid diverged (NaN mean velocity) at step {}", solver.steps()));
  }
}

/// The coupler's side of the fluid. Reads the key files: call it before building the lattice, so
/// a bad one stops the program first.
coupler::FluidConfig side_config(const Scene& scene, const CoupledOptions& opt) {
  const auto curve =
      coupler::curve_for(opt.endpoint, opt.security, coupler::Side::server, "dld-fluid");
  coupler::FluidConfig fc;
  fc.scene = coupler::scene_identity(scene, static_cast<std::uint32_t>(opt.cells));
  fc.endpoints = coupler::peer_endpoints(opt.endpoint, static_cast<std::size_t>(opt.peers));
  fc.options.timeout =
      std::chrono::milliseconds(static_cast<long>(scene.coupling.timeout_s * 1000));
  fc.options.curve = curve;
  return fc;
}

}  // namespace

int serve_coupled(const Scene& scene, const CoupledOptions& opt) {
  const coupler::FluidConfig fc = side_config(scene, opt);
  FluidSolver solver(fluid_config(scene));
  const ImmersedBoundary ib(solver.lattice(), ib_kernel_from_name(scene.coupling.ib_kernel));
  coupler::FluidSide side(fc);
  const DldCell box = scene.cell_lu();
  side.set_periodic_box({box.lambda, box.shift});  // for the contact halo of a split suspension

  // The run file's time series up to the checkpoint comes with it: a resumed run file is whole.
  std::vector<double> timeseries;
  if (!opt.resume.empty()) {
    spdlog::info("resumed from {} at step {}", opt.resume,
                 read_checkpoint(opt.resume, scene, solver, &timeseries));
  }
  std::unique_ptr<FluidRunFile> out;
  if (!opt.output.empty()) out = std::make_unique<FluidRunFile>(scene, opt.output, timeseries);
  std::int64_t checkpointed = -1;  // once per step: a second write would push out .prev
  auto checkpoint = [&] {
    if (opt.checkpoint.empty() || solver.steps() == checkpointed) return;
    checkpointed = solver.steps();
    write_checkpoint(opt.checkpoint, scene, solver, out ? out->timeseries() : timeseries);
    spdlog::info("checkpoint at step {}: {}", solver.steps(), opt.checkpoint);
  };
  try {
    side.initialize();
    spdlog::info("coupled with {} membrane process(es), {} markers; {} kernel", side.peer_count(),
                 side.node_count(), scene.coupling.ib_kernel);
    const std::unique_ptr<ViscosityContrast> contrast = make_contrast(scene, solver, side);
    bool warned_unpaired = false;
    std::vector<double> velocity;
    const auto start = std::chrono::steady_clock::now();
    std::int64_t steps = 0;
    PhaseTimes t;
    signal(SIGINT, on_sigint);
    signal(SIGBUS, on_sigbus);
    // Interrupted, the run ends at the next step a resume repeats exactly (see
    // CouplingParams::exact_resume_every); the membranes end there too.
    const std::int64_t exact_every = scene.coupling.exact_resume_every();
    std::vector<double> held_x;  // the nodes during held steps, moved here as the membranes would
    while ((!g_stop || solver.steps() % exact_every != 0) && side.receive()) {
      t.lap(t.wait);
      // Held steps (the membranes' forces held for n > 1 steps): the nodes move by X += U dt
      // (dt = 1) here after each step, as the membranes would move them, bit for bit.
      const std::uint64_t n = side.held_steps();
      if (n > 1 && scene.coupling.force_every == 1)
        throw std::runtime_error(fmt::format(
            "a membrane process holds its forces {} steps, but this fluid couples exactly "
            "([coupling] force_every 1, or --exact-coupling): give both programs the same "
            "coupling (dld-run does)",
            n));
      std::span<const double> x = side.positions();
      if (n > 1) {
        held_x.assign(x.begin(), x.end());
        x = held_x;
      }
      for (std::uint64_t j = 0; j < n; ++j) {
        // [coupling] spread_held: the force field of the last force update stays (and with
        // interpolation_held its weights too).
        const bool spread = !scene.coupling.spread_held || steps == 0 ||
                            solver.steps() % scene.coupling.force_every == 0;
        const bool weights_held = !spread && scene.coupling.interpolation_held;
        if (spread) ib.spread(x, side.forces(), solver.force_field());
        t.lap(t.spread);
        if (contrast) update_contrast(*contrast, scene, solver, x, steps == 0, warned_unpaired);
        t.lap(t.contrast);
        solver.step();
        t.lap(t.fluid);
        require_finite_lattice(solver);
        velocity.resize(x.size());
        if (weights_held) {
          ib.interpolate_at_spread(solver.velocity_field(), velocity);
        } else {
          ib.interpolate(x, solver.velocity_field(), velocity);
        }
        require_resolved_velocities(velocity, side, solver.steps());
        if (n == 1) {
          side.send_velocities(velocity);
        } else {
          for (std::size_t i = 0; i < held_x.size(); ++i) held_x[i] += velocity[i];
          if (j + 1 == n) side.send_positions(held_x);
        }
        t.lap(t.interpolate);
        ++steps;
        if (opt.checkpoint_every > 0 && solver.steps() % opt.checkpoint_every == 0) checkpoint();
        if (steps % scene.run.log_every == 0) log_progress(scene, solver, out.get(), steps, start);
      }
    }
    if (out && scene.output.fields) out->snapshot(solver);
    side.finalize();
    checkpoint();
    spdlog::info("{} after {} steps", g_stop ? "interrupted: run ended" : "membranes ended the run",
                 steps);
    t.report(steps);
    return 0;
  } catch (const coupler::CouplerError& e) {
    spdlog::error("{}", e.what());
    return 3;
  } catch (const std::exception& e) {
    side.abort(e.what());  // tell the membranes why, so they stop naming the fluid
    spdlog::error("{}", e.what());
    return 1;
  }
}

}  // namespace dld::fluid
