// SPDX-License-Identifier: MIT
// dld-tracers: the second membrane program. Massless tracer particles that follow the fluid
// (zero force, X += U dt), speaking the same protocol as dld-membrane to the same dld-fluid:
// the proof that the membrane side can be swapped. Each tracer is a "cell" of one node.
// Positions are exchanged in lattice units; trajectories are written in device coordinates (um).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <random>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/membrane_side.hpp"
#include "coupler/scene_identity.hpp"
#include "coupler/security_options.hpp"
#include "shared/cli_checks.hpp"
#include "shared/dld_geometry.hpp"
#include "shared/guarded_main.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"
#include "shared/log.hpp"
#include "shared/scene.hpp"

namespace {
// Ctrl-C (or dld-run passing one on) ends the run cleanly: the fluid gets a shutdown frame.
volatile sig_atomic_t g_stop = 0;
void on_sigint(int) {
  g_stop = 1;
}

struct Args {
  std::string scene_path, endpoint, output;
  int count = 16, peer = 0, peers = 1;
  std::int64_t steps = 1000, sample_every = 100;
  unsigned seed = 1;
  dld::coupler::SecurityArgs security;
};

/// Random start positions in the fluid, at least 2 nodes from the pillar and the walls.
std::vector<double> start_positions(const dld::DldCell& cell, const Args& a) {
  std::mt19937 rng(a.seed + static_cast<unsigned>(a.peer));
  std::uniform_real_distribution<double> ux(0, cell.lambda), uz(2.0, cell.depth - 2.0);
  std::vector<double> x;
  while (x.size() < 3 * static_cast<std::size_t>(a.count)) {
    const double p[3] = {ux(rng), ux(rng), cell.depth > 4.0 ? uz(rng) : 0.5 * cell.depth};
    if (cell.pillar_distance(p[0], p[1]) < 2.0) continue;
    x.insert(x.end(), p, p + 3);
  }
  return x;
}

dld::coupler::MembraneConfig coupler_config(const dld::Scene& scene, const Args& a) {
  dld::coupler::MembraneConfig mc;
  mc.scene = dld::coupler::scene_identity(scene, static_cast<std::uint32_t>(a.count * a.peers));
  mc.endpoint = dld::coupler::peer_endpoints(a.endpoint, static_cast<std::size_t>(a.peers))[a.peer];
  mc.name = fmt::format("tracers-{}", a.peer);
  mc.peer_index = static_cast<std::uint32_t>(a.peer);
  mc.peer_count = static_cast<std::uint32_t>(a.peers);
  mc.first_cell = static_cast<std::uint32_t>(a.peer * a.count);
  mc.cell_nodes.assign(static_cast<std::size_t>(a.count), 1);
  mc.options.timeout =
      std::chrono::milliseconds(static_cast<long>(scene.coupling.timeout_s * 1000));
  mc.options.curve =
      dld::coupler::curve_for(mc.endpoint, a.security, dld::coupler::Side::client, "dld-tracers");
  return mc;
}

/// The trajectories: rows of step, then x y z per tracer in device um.
void write_samples(const std::string& output, const std::vector<double>& samples,
                   std::size_t tracers, const dld::Scene& scene) {
  std::filesystem::path p(output);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  dld::H5File f(output, dld::H5File::Mode::kCreate);
  const std::uint64_t rows = samples.size() / (1 + 3 * tracers);
  f.write("/tracers/samples", samples.data(), {rows, 1 + 3 * tracers});
  f.attribute("/tracers/samples", "columns",
              std::string("step, then x y z [um, device frame] per tracer"));
  f.attribute("/tracers", "count", static_cast<std::int64_t>(tracers));
  f.attribute("/tracers", "dt_s", scene.units().dt_s());
}

/// Moves the tracers with the fluid until the step limit, Ctrl-C or the fluid's end.
int run(const Args& a) {
  if (a.peer >= a.peers)
    throw dld::InputError(fmt::format("--peer {}: expected below --peers {}", a.peer, a.peers));
  const dld::Scene scene = dld::load_scene(a.scene_path);
  std::vector<double> x = start_positions(scene.cell_lu(), a);
  dld::coupler::MembraneSide side(coupler_config(scene, a));
  side.initialize();
  const std::vector<double> force(x.size(), 0.0);
  std::vector<double> u(x.size());
  std::vector<double> samples;
  auto sample = [&](std::int64_t step) {
    samples.push_back(static_cast<double>(step));
    for (std::size_t m = 0; m < x.size(); ++m) samples.push_back(x[m] * scene.lattice.dx_um);
  };
  sample(0);
  std::int64_t s = 0;
  signal(SIGINT, on_sigint);
  for (; s < a.steps && !g_stop; ++s) {
    if (!side.advance(x, force, u)) break;
    for (std::size_t m = 0; m < x.size(); ++m) x[m] += u[m];  // dt = 1 in lattice units
    if ((s + 1) % a.sample_every == 0) sample(s + 1);
  }
  side.finalize();
  // Positions were never folded: they are device coordinates already (the fluid folds them).
  spdlog::info("{} tracers ran {} steps", a.count, s);
  if (!a.output.empty()) write_samples(a.output, samples, x.size() / 3, scene);
  return 0;
}

}  // namespace

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-tracers: tracer particles carried by dld-fluid (a second membrane program)"};
  Args a;
  app.add_option("scene", a.scene_path, "scene file (TOML)")->required();
  app.add_option("--connect", a.endpoint,
                 "the fluid's base endpoint (as given to dld-fluid --serve)")
      ->required();
  app.add_option("--count", a.count, "tracers")->check(CLI::Range(1, 1000000));
  app.add_option("--peer", a.peer, "this program's peer index")->check(CLI::NonNegativeNumber);
  app.add_option("--peers", a.peers, "membrane programs in the run")->check(CLI::Range(1, 64));
  app.add_option("--steps", a.steps, "steps to run, then end the run")->check(dld::step_count());
  app.add_option("--sample-every", a.sample_every, "steps between trajectory samples")
      ->check(CLI::PositiveNumber);
  app.add_option("--seed", a.seed, "random seed of the start positions");
  app.add_option("-o,--output", a.output, "trajectory file (HDF5)");
  dld::coupler::add_security_options(app, a.security, dld::coupler::Side::client);
  CLI11_PARSE(app, argc, argv);
  dld::setup_logging(fmt::format("dld-tracers-{}", a.peer));
  try {
    return run(a);
  } catch (const dld::coupler::CouplerError& e) {
    spdlog::error("{}", e.what());
    return 3;
  } catch (const dld::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-tracers", run_main, argc, argv);
}
