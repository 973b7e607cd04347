// SPDX-License-Identifier: MIT
// dld-membrane: the membrane side. With a standalone task in the scene ([membrane.stretch] or
// [membrane.relax]) it runs without fluid; otherwise it checks the scene, meshes the cells and
// prints the resolved membrane set-up (coupled runs are started by the coupler's launcher).
#include <fmt/format.h>
#include <omp.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "coupler/security_options.hpp"
#include "membrane/clearance.hpp"
#include "membrane/coupled_main.hpp"
#include "membrane/membrane_scene.hpp"
#include "membrane/mesh_quality.hpp"
#include "membrane/packing.hpp"
#include "shared/cli_checks.hpp"
#include "shared/guarded_main.hpp"
#include "shared/h5file.hpp"
#include "shared/log.hpp"
#include "shared/openmp_wait.hpp"

namespace {

using namespace dld;
using namespace dld::membrane;

void run_stretch(const Scene& scene, const MembraneScene& m, const std::string& output) {
  const LatticeUnits u = scene.units();
  std::vector<double> forces_lu;
  for (double f : m.stretch->forces_pN) forces_lu.push_back(u.force_lu(f * 1e-12));
  const auto points = stretch_cell(m.reference_lu, m.mechanics, forces_lu, m.stretch->options);
  std::vector<double> f_pN, da, dt, dv;
  std::string csv =
      "# dld-membrane optical-tweezers stretch: force [pN], D_A [um], D_T [um], V/V0-1, converged\n"
      "force_pN,axial_um,transverse_um,volume_change,converged\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    f_pN.push_back(m.stretch->forces_pN[i]);
    da.push_back(u.length_m(p.axial) * 1e6);
    dt.push_back(u.length_m(p.transverse) * 1e6);
    dv.push_back(p.volume_change);
    spdlog::info("F {:7.2f} pN: D_A {:6.3f} um, D_T {:6.3f} um, dV/V {:+.2e}, {} iterations{}",
                 f_pN.back(), da.back(), dt.back(), p.volume_change, p.iterations,
                 p.converged ? "" : " (NOT converged)");
    csv += fmt::format("{},{:.6f},{:.6f},{:.3e},{}\n", f_pN.back(), da.back(), dt.back(), dv.back(),
                       p.converged ? 1 : 0);
  }
  if (!m.stretch->output_csv.empty()) {
    std::filesystem::path p(m.stretch->output_csv);
    if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
    std::ofstream(p) << csv;
    spdlog::info("wrote {}", p.string());
  }
  std::filesystem::path h5(output);
  if (h5.has_parent_path()) std::filesystem::create_directories(h5.parent_path());
  H5File file(output, H5File::Mode::kCreate);
  file.write("/stretch/force_pN", f_pN);
  file.write("/stretch/axial_um", da);
  file.write("/stretch/transverse_um", dt);
  file.write("/stretch/volume_change", dv);
  file.attribute("/", "scene", scene.file);
  file.attribute("/", "mesh_faces", static_cast<std::int64_t>(m.reference_lu.face_count()));
  spdlog::info("wrote {}", output);
}

void run_relax(const Scene& scene, const MembraneScene& m) {
  CellSet cells(m.reference_lu, m.mechanics);
  const double s = m.relax->initial_stretch;
  Points x = m.reference_lu.nodes;
  x.row(0) *= s;
  x.row(1) /= s;
  cells.add_cell(x);
  const double v0 = enclosed_volume(m.reference_lu);
  spdlog::info("relaxing a cell stretched by {} in x, 1/{} in y (volume {:+.3e} off)", s, s,
               cells.volume(0) / v0 - 1);
  const RelaxResult r = relax_overdamped(
      cells, m.relax->options,
      [](int step, double e, double fmax) {
        spdlog::info("step {:6d}: energy {:.6e}, max node force {:.3e}", step, e, fmax);
      },
      1000);
  const double err = (cells.positions().colwise() - cells.centroid(0) - m.reference_lu.nodes)
                         .colwise()
                         .norm()
                         .maxCoeff();
  spdlog::info(
      "relaxed in {} steps: energy {:.3e}, max force {:.3e}, volume drift {:+.3e}, largest node "
      "distance from rest shape {:.3e} dx",
      r.steps, r.energy, r.max_force, cells.volume(0) / v0 - 1, err);
  (void)scene;
}

/// --pack: the packed state of each count (loaded or packed and saved), one line each.
void run_pack(const Scene& scene, const MembraneScene& m, std::vector<int> counts) {
  if (counts.empty()) {
    if (!m.pack) throw dld::InputError(scene.file + ": --pack needs [cells] count or --counts");
    counts.push_back(m.pack->count);
  }
  const DldCell box = scene.cell_lu();
  const double dx = scene.lattice.dx_um;
  const double range = m.pack ? m.pack->clearance_lu : (m.contact ? m.contact->range : 1.0);
  std::printf("# packed initial states: %s (dx %.3g um, %d faces, contact range %.3g um)\n",
              scene.file.c_str(), dx, m.reference_lu.face_count(), range * dx);
  std::printf(
      "# cells  Ht_%%   gap_cells_um gap_walls_um gap_pillar_um  nodes_inside  tilt_deg  "
      "pack_cpu_s  pack_wall_s  file\n");
  for (int count : counts) {
    if (count < 1)
      throw dld::InputError(fmt::format("--counts: expected counts >= 1, got {}", count));
    const CachedPacking p = packed_scene_cells(m, scene, count);
    CellSet cells(m.reference_lu, MembraneMechanics{});
    const int n = p.cells.nodes_per_cell;
    for (int k = 0; k < count; ++k)
      cells.add_cell(Points(p.cells.positions.middleCols(Eigen::Index{k} * n, n)));
    // Measured on the state itself, not taken from the file.
    const Clearances g = clearances(cells.positions(), n, box, box.lambda);
    const int inside = nodes_inside_other_cells(cells.positions(), m.reference_lu.faces, n, box);
    std::printf("%7d  %5.2f  %12.3f %12.3f %13.3f  %12d  %8.1f  %10.1f  %11.1f  %s%s\n", count,
                100.0 * haematocrit(cells, box), g.cells * dx, g.walls * dx, g.pillar * dx, inside,
                largest_tilt_deg(cells.positions(), n), p.cells.report.cpu_seconds,
                p.cells.report.seconds, p.file.empty() ? "(not saved)" : p.file.c_str(),
                p.from_cache ? " (loaded)" : "");
    std::fflush(stdout);
  }
}

}  // namespace

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-membrane: red-blood-cell membranes (meshes, models, contact; standalone runs)"};
  std::string scene_path, output;
  bool verbose = false;
  dld::membrane::CoupledArgs coupled;
  app.add_option("scene", scene_path, "scene file (TOML)")->required();
  dld::coupler::add_security_options(app, coupled.security, dld::coupler::Side::client);
  app.add_option("--connect", coupled.endpoint,
                 "coupled mode: the fluid's endpoint (dld-fluid --serve)");
  app.add_option("--peer", coupled.peer, "this process's index among the membrane processes")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--peers", coupled.peers, "membrane processes in the run")
      ->check(CLI::Range(1, 64));
  app.add_option("--steps", coupled.steps, "coupled mode: steps to run")->check(dld::step_count());
  app.add_option("--sample-every", coupled.sample_every, "coupled mode: steps between samples")
      ->check(CLI::PositiveNumber);
  app.add_option("--pillars", coupled.pillars,
                 "coupled mode: end the run once every cell has passed this many pillars")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--until-mode-certain", coupled.stop_when_mode_certain,
               "coupled mode: end the run once every cell's mode (zigzag/displacement) is certain");
  dld::add_checkpoint_options(app, coupled.checkpoint, coupled.checkpoint_every, coupled.resume);
  app.add_flag("--exchange-every-step", coupled.exchange_every_step,
               "coupled mode: exchange with the fluid every step while forces are held too (the "
               "same results, slower; default: the fluid runs the held steps)");
  app.add_option("-o,--output", output,
                 "HDF5 output of standalone runs (default: the scene's output.file)");
  bool pack = false;
  std::vector<int> pack_counts;
  app.add_flag("--pack", pack,
               "pack the scene's [cells] count (or --counts) at random: Ht, gaps, time, file");
  app.add_option("--counts", pack_counts, "with --pack: cell counts, e.g. 3,6,12,15,17")
      ->delimiter(',');
  bool check = false;
  app.add_flag("--check", check,
               "validate the scene's membrane part (and make its mesh), print it, and exit");
  app.add_flag("-v,--verbose", verbose, "debug logging");
  int threads = 0;
  app.add_option("--threads", threads, "coupled mode: OpenMP threads (overrides run.threads)")
      ->check(CLI::Range(1, 1024));
  bool exact_coupling = false;
  app.add_flag("--exact-coupling", exact_coupling,
               "coupled mode: forces every step, whatever the scene's [coupling] holds (dld-run "
               "--exact-coupling-for; the fluid must be told too)");
  CLI11_PARSE(app, argc, argv);
  dld::setup_logging("dld-membrane", verbose);
  try {
    dld::Scene scene = dld::load_scene(scene_path, false);
    if (exact_coupling) scene.coupling.make_exact();
    const MembraneScene m = read_membrane_scene(scene);
    scene.document->reject_unknown({"coupling"});
    spdlog::info("{}", m.describe(scene));
    spdlog::info("mesh: {}", describe(mesh_quality(m.reference_lu)));
    if (check) return 0;
    if (pack) {
      run_pack(scene, m, pack_counts);
      return 0;
    }
    if (!coupled.endpoint.empty()) {
      // A coupled run's programs take turns on the same cores: both honour [run] threads, so
      // that runs side by side (dld-sweep --jobs) do not oversubscribe them.
      const int t = threads > 0 ? threads : scene.run.threads;
      if (t > 0) omp_set_num_threads(t);
      spdlog::info("{} OpenMP threads ({})", omp_get_max_threads(), dld::openmp_wait_settings());
      if (coupled.peer >= coupled.peers)
        throw dld::InputError(
            fmt::format("--peer {}: expected below --peers {}", coupled.peer, coupled.peers));
      coupled.output = output;
      return run_coupled(scene, m, coupled);
    }
    if (m.stretch) {
      run_stretch(scene, m, output.empty() ? scene.output.file : output);
    } else if (m.relax) {
      run_relax(scene, m);
    } else {
      const CellSet cells = build_cells(m, scene);
      spdlog::info(
          "{} cells, Ht = {:.2f} % (no standalone task: coupled runs are started by dld-run)",
          cells.cell_count(), 100.0 * haematocrit(cells, scene.cell_lu()));
    }
  } catch (const dld::InputError& e) {
    std::fprintf(stderr, "dld-membrane: error: %s\n", e.what());
    return 1;
  }
  return 0;
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-membrane", run_main, argc, argv);
}
