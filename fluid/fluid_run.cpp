// SPDX-License-Identifier: MIT
#include "fluid/fluid_run.hpp"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <memory>

#include "fluid/fluid_output.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/observables.hpp"

namespace dld::fluid {

FluidRunSummary run_fluid(const Scene& scene, const FluidRunOptions& opt) {
  const LatticeUnits units = scene.units();
  const DldCell cell = scene.cell_lu();
  const std::int64_t max_steps = opt.max_steps >= 0 ? opt.max_steps : scene.run.max_steps;
  FluidSolver solver(fluid_config(scene));
  const double mass0 = solver.total_mass();
  // Flux in lattice units (nodes^3 per step) to m^3/s.
  const double flux_unit = units.dx_m() * units.dx_m() * units.dx_m() / units.dt_s();

  std::unique_ptr<FluidRunFile> out;
  FluidRunSummary sum;
  sum.output = opt.output.empty() ? scene.output.file : opt.output;
  if (opt.write_file) out = std::make_unique<FluidRunFile>(scene, sum.output);

  const auto start = std::chrono::steady_clock::now();
  double last_ux = 0.0;
  while (solver.steps() < max_steps) {
    solver.step();
    const std::int64_t s = solver.steps();
    if (out && scene.output.fields && scene.output.snapshot_every > 0 &&
        s % scene.output.snapshot_every == 0)
      out->snapshot(solver);
    if (s % scene.run.log_every != 0 && s != max_steps) continue;
    const auto u = solver.mean_velocity();
    const double change = std::abs(u[0] - last_ux) / std::max(std::abs(u[0]), 1e-300);
    last_ux = u[0];
    const double flux = gap_profile(solver, cell).flux * flux_unit;
    if (out) out->sample(solver, flux);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double mlups = static_cast<double>(s) * solver.lattice().fluid_nodes() / secs / 1e6;
    if (opt.progress) {
      const double eta = secs / static_cast<double>(s) * static_cast<double>(max_steps - s);
      spdlog::info(
          "step {:>8}/{}  <u_x> {:.5g} m/s  <u_y>/<u_x> {:+.2e}  change {:.2e}  {:.1f} MLUPS  "
          "ETA {:.0f} s (or earlier if steady)",
          s, max_steps, units.velocity_m_s(u[0]), u[1] / u[0], change, mlups, eta);
    }
    if (!std::isfinite(u[0]))
      throw std::runtime_error(fmt::format("fluid diverged (NaN mean velocity) at step {}", s));
    if (scene.run.steady_tolerance > 0 && change < scene.run.steady_tolerance &&
        std::abs(u[1]) < scene.run.steady_tolerance * std::abs(u[0])) {
      sum.steady = true;
      break;
    }
  }
  const double secs =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto u = solver.mean_velocity();
  const GapProfile profile = gap_profile(solver, cell);
  const double eps = scene.cell_um.shift / scene.cell_um.lambda;
  const double nu = scene.fluid.viscosity_Pa_s / scene.fluid.density_kg_m3;
  sum.steps = solver.steps();
  sum.mean_ux_m_s = units.velocity_m_s(u[0]);
  sum.mean_uy_m_s = units.velocity_m_s(u[1]);
  sum.reynolds = sum.mean_ux_m_s * scene.cell_um.gap() * 1e-6 / nu;
  sum.gap_flux_m3_s = profile.flux * flux_unit;
  sum.separation_um = band_width(profile, eps) * scene.lattice.dx_um;
  sum.relative_mass_change = std::abs(solver.total_mass() - mass0) / mass0;
  sum.mlups = static_cast<double>(sum.steps) * solver.lattice().fluid_nodes() / secs / 1e6;
  sum.ms_per_step = sum.steps > 0 ? 1e3 * secs / static_cast<double>(sum.steps) : 0.0;
  if (out) {
    if (scene.output.fields) out->snapshot(solver);
    out->result("separation_distance_um", sum.separation_um, "um");
    out->result("gap_flux_m3_s", sum.gap_flux_m3_s, "m^3/s");
    out->result("reynolds", sum.reynolds, "1");
    out->result("mean_ux_m_s", sum.mean_ux_m_s, "m/s");
    out->result("steps", static_cast<double>(sum.steps), "1");
    std::vector<double> y_um, q;
    for (std::size_t i = 0; i < profile.y.size(); ++i) {
      y_um.push_back(profile.y[i] * scene.lattice.dx_um);
      q.push_back(units.velocity_m_s(profile.q[i]) * units.dx_m());
    }
    out->result_array("gap_profile_y_um", y_um);
    out->result_array("gap_profile_q_m2_s", q);
  }
  return sum;
}

}  // namespace dld::fluid
