// SPDX-License-Identifier: MIT
// dld-fluid: runs a fluid-only scene (no membrane process) and reports the streamline separation
// distance of the DLD cell.
#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>
#include <sys/resource.h>

#include <CLI/CLI.hpp>

#include "coupler/security_options.hpp"
#include "fluid/coupled_main.hpp"
#include "fluid/fluid_run.hpp"
#include "shared/cli_checks.hpp"
#include "shared/guarded_main.hpp"
#include "shared/input_error.hpp"
#include "shared/log.hpp"
#include "shared/openmp_wait.hpp"
#include "shared/scene.hpp"

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-fluid: lattice-Boltzmann flow through one DLD unit cell"};
  std::string scene_path;
  std::int64_t steps = -1;
  int threads = -1;
  std::string output;
  bool check_only = false;
  dld::fluid::CoupledOptions coupled;
  app.add_option("scene", scene_path, "scene file (TOML)")->required();
  app.add_option("--steps", steps, "step limit (overrides run.max_steps)")
      ->check(dld::step_count());
  app.add_option("--threads", threads, "OpenMP threads (overrides run.threads)")
      ->check(CLI::Range(1, 1024));
  app.add_option("-o,--output", output, "run file (overrides output.file)");
  app.add_flag("--check", check_only, "validate the scene, print it resolved, and exit");
  app.add_option(
      "--serve", coupled.endpoint,
      "coupled mode: serve membrane programs at this endpoint (ipc://path, tcp://host:port)");
  dld::coupler::add_security_options(app, coupled.security, dld::coupler::Side::server);
  app.add_option("--peers", coupled.peers, "membrane processes to serve (coupled mode)")
      ->check(CLI::Range(1, 64));
  dld::add_checkpoint_options(app, coupled.checkpoint, coupled.checkpoint_every, coupled.resume);
  app.add_option("--cells", coupled.cells, "total cells of the membrane processes (coupled mode)")
      ->check(CLI::Range(0, 100000));
  bool exact_coupling = false;
  app.add_flag("--exact-coupling", exact_coupling,
               "coupled mode: forces, viscosity field and spreading every step, whatever the "
               "scene's [coupling] holds (dld-run --exact-coupling-for)");
  CLI11_PARSE(app, argc, argv);

  dld::setup_logging("dld-fluid");
  try {
    dld::Scene scene = dld::load_scene(scene_path);
    if (exact_coupling) scene.coupling.make_exact();
    fmt::print("{}\n", scene.describe());
    if (check_only) return 0;
    const int t = threads > 0 ? threads : scene.run.threads;
    if (t > 0) omp_set_num_threads(t);
    spdlog::info("{} OpenMP threads ({})", omp_get_max_threads(), dld::openmp_wait_settings());
    if (!coupled.endpoint.empty()) {
      coupled.output = output;
      return dld::fluid::serve_coupled(scene, coupled);
    }
    dld::fluid::FluidRunOptions opt;
    opt.max_steps = steps;
    opt.output = output;
    const auto r = dld::fluid::run_fluid(scene, opt);
    fmt::print("steps {}{}\n", r.steps,
               r.steady ? " (steady)" : " (step limit reached, not steady)");
    fmt::print("mean velocity u_x = {:.6g} m/s, u_y = {:.3g} m/s, Re = U G / nu = {:.4g}\n",
               r.mean_ux_m_s, r.mean_uy_m_s, r.reynolds);
    fmt::print("gap flux Q = {:.6g} m^3/s (= {:.6g} um^3/s)\n", r.gap_flux_m3_s,
               r.gap_flux_m3_s * 1e18);
    fmt::print(
        "separation distance s = {:.4f} um (band carrying eps = d/lambda = {:.5f} of the gap "
        "flux)\n",
        r.separation_um, scene.cell_um.shift / scene.cell_um.lambda);
    fmt::print("relative mass change {:.2e}; {:.1f} MLUPS; time per step {:.4f} ms\n",
               r.relative_mass_change, r.mlups, r.ms_per_step);
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    fmt::print("peak resident memory {:.1f} MiB\n", usage.ru_maxrss / 1024.0);
    fmt::print("wrote {} (open {} in ParaView)\n", r.output,
               r.output.substr(0, r.output.rfind('.')) + ".xmf");
    return 0;
  } catch (const dld::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-fluid", run_main, argc, argv);
}
