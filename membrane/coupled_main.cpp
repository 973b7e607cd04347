// SPDX-License-Identifier: MIT
// The coupled mode of dld-membrane: the cells of this process (an equal share of the scene's
// [[cells.cell]] list) exchange positions and forces for velocities with dld-fluid every step,
// and move with the fluid (no-slip: X += U dt, dt = 1 in lattice units).
// Output (membrane/cells_part_file): per-cell centroid (device frame, um: cells are never folded
// into the box) and volume every `sample_every` steps, and with [output] mesh_every the nodes of
// every cell every that many steps (membrane/mesh_output), each appended and flushed as taken.
// Progress lines give pillars passed, steps/s, the ETA to the pillar target and the modes.
#include "membrane/coupled_main.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <optional>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/membrane_side.hpp"
#include "coupler/scene_identity.hpp"
#include "membrane/cells_part_file.hpp"
#include "membrane/mesh_output.hpp"
#include "membrane/run_checkpoint.hpp"
#include "membrane/stability_guard.hpp"
#include "shared/column_tracker.hpp"

namespace dld::membrane {
namespace {

volatile sig_atomic_t g_stop = 0;
void on_sigint(int) {
  g_stop = 1;
}

std::optional<double> capillary_number(const Scene& scene) {
  if (const auto* v =
          scene.document->root().at_path("membrane.capillary_number").as_floating_point())
    return v->get();
  return std::nullopt;
}

}  // namespace

int run_coupled(const Scene& scene, const MembraneScene& m, const CoupledArgs& a) {
  const CellSet all = build_cells(m, scene);
  const int total = all.cell_count();
  const int first = total * a.peer / a.peers, last = total * (a.peer + 1) / a.peers;
  // This process's share; contact with cells of other processes is not seen (one process sees all).
  CellSet cells(all.reference(), all.mechanics(), all.contact());
  for (int k = first; k < last; ++k) cells.add_cell(Points(all.cell_positions(k)));
  std::vector<double> v0;
  v0.reserve(static_cast<std::size_t>(cells.cell_count()));
  for (int k = 0; k < cells.cell_count(); ++k) v0.push_back(cells.volume(k));

  coupler::MembraneConfig mc;
  mc.scene = coupler::scene_identity(scene, static_cast<std::uint32_t>(total));
  mc.endpoint = coupler::peer_endpoints(a.endpoint, static_cast<std::size_t>(a.peers))[a.peer];
  mc.name = fmt::format("membrane-{}", a.peer);
  mc.peer_index = static_cast<std::uint32_t>(a.peer);
  mc.peer_count = static_cast<std::uint32_t>(a.peers);
  mc.first_cell = static_cast<std::uint32_t>(first);
  mc.cell_nodes.assign(static_cast<std::size_t>(cells.cell_count()),
                       static_cast<std::uint32_t>(cells.nodes_per_cell()));
  mc.options.timeout =
      std::chrono::milliseconds(static_cast<long>(scene.coupling.timeout_s * 1000));
  coupler::MembraneSide side(mc);
  // Every cell shares the reference mesh's triangles; the fluid needs them for the inside/outside
  // viscosity field (protocol v2), so they are sent once, in the hello.
  side.set_cell_surfaces(
      std::vector<std::uint32_t>(static_cast<std::size_t>(cells.cell_count()),
                                 static_cast<std::uint32_t>(cells.reference().face_count())),
      face_indices(cells.reference(), cells.cell_count()));

  const double dx_um = scene.lattice.dx_um;
  const RunFacts facts{
      cells.cell_count(),  first,      scene.units().dt_s(),    scene.cell_um.lambda,
      scene.cell_um.shift, scene.name, capillary_number(scene), m.expected_mode};
  auto centroids_um = [&] {
    std::vector<Eigen::Vector3d> c;
    c.reserve(static_cast<std::size_t>(cells.cell_count()));
    for (int k = 0; k < cells.cell_count(); ++k) c.push_back(cells.centroid(k) * dx_um);
    return c;
  };
  // Resuming: the cells' nodes and the samples so far come from the checkpoint, and the tracker
  // replays the samples from the cells' starts.
  const RunCheckpoint expected{0,  scene.hash, first, cells.cell_count(), cells.nodes_per_cell(),
                               {}, {}};
  std::int64_t offset = 0;
  std::vector<double> rows;
  if (!a.resume.empty()) {
    RunCheckpoint c = read_run_checkpoint(a.resume, expected);
    cells.positions() = c.positions;
    rows = std::move(c.rows);
    offset = c.step;
    spdlog::info("resumed from {} at step {}", a.resume, offset);
  }
  const std::size_t width = 1 + 4 * static_cast<std::size_t>(cells.cell_count());
  auto row_centroids = [&](std::size_t r) {
    std::vector<Eigen::Vector3d> c;
    for (int k = 0; k < cells.cell_count(); ++k) {
      const double* v = &rows[r * width + 1 + 4 * static_cast<std::size_t>(k)];
      c.emplace_back(v[0], v[1], v[2]);
    }
    return c;
  };
  ColumnTracker tracker(facts.lambda_um, facts.row_shift_um,
                        rows.empty() ? centroids_um() : row_centroids(0));
  for (std::size_t r = 1; r < rows.size() / width; ++r) tracker.update(row_centroids(r));
  double done_at_start = 0;
  for (int k = 0; k < cells.cell_count(); ++k)
    done_at_start = k == 0 ? tracker.fractional_columns(k)
                           : std::min(done_at_start, tracker.fractional_columns(k));
  // Stops the run at once when a cell goes unstable; no checkpoint is written after that, so the
  // last one on disk is the last good state.
  StabilityGuard guard(scene.cell_lu(), dx_um, GuardLimits{}, v0);
  auto checkpoint = [&](std::int64_t step) {
    if (a.checkpoint.empty()) return;
    RunCheckpoint c = expected;
    c.step = step;
    c.positions = cells.positions();
    c.rows = rows;
    write_run_checkpoint(a.checkpoint, c);
  };
  // Made once connected (an error then reaches the fluid through the coupler); on resume it
  // starts from the checkpoint's samples.
  std::optional<CellsPartFile> part;
  std::optional<MeshOutput> mesh;
  const std::int64_t mesh_every = scene.output.mesh_every;
  auto open_output = [&] {
    if (a.output.empty()) {
      if (mesh_every > 0) spdlog::warn("[output] mesh_every: no output file (-o), no meshes");
      return;
    }
    part.emplace(a.output, facts, rows,
                 a.resume.empty() ? std::nullopt : std::optional<std::int64_t>(offset));
    if (mesh_every > 0) {
      mesh.emplace(part->file(), cells.reference(), cells.cell_count(), first, facts.dt_s);
    } else {
      // An earlier run's XDMF would name meshes this part file does not hold.
      std::error_code ignored;
      std::filesystem::remove(mesh_xdmf_path(a.output), ignored);
    }
  };
  auto sample = [&](std::int64_t step) {
    const std::size_t begin = rows.size();
    rows.push_back(static_cast<double>(step));
    const auto c = centroids_um();
    for (int k = 0; k < cells.cell_count(); ++k)
      rows.insert(rows.end(),
                  {c[k].x(), c[k].y(), c[k].z(), cells.volume(k) * dx_um * dx_um * dx_um});
    tracker.update(c);
    if (part)
      part->append(
          std::vector<double>(rows.begin() + static_cast<std::ptrdiff_t>(begin), rows.end()));
  };
  auto sample_mesh = [&](std::int64_t step) {
    if (mesh) mesh->append(step, cells.positions() * dx_um);
  };
  auto finish = [&] {
    if (part) part->file().flush();
  };
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto progress = [&](std::int64_t step) {
    const double secs = std::chrono::duration<double>(Clock::now() - start).count();
    double done = 0;  // columns of the slowest cell, fractional
    for (int k = 0; k < cells.cell_count(); ++k)
      done = k == 0 ? tracker.fractional_columns(k) : std::min(done, tracker.fractional_columns(k));
    std::string eta;
    if (a.pillars > 0 && done - done_at_start > 0.05)
      eta = fmt::format("  ETA {:.0f} s", secs * (a.pillars - done) / (done - done_at_start));
    std::string modes;
    for (int k = 0; k < cells.cell_count() && k < 4; ++k)
      modes += fmt::format(
          " {}:{}{}", first + k, to_string(tracker.mode(k)),
          tracker.mode(k) != TransportMode::kUndecided && !tracker.certain(k) ? "?" : "");
    spdlog::info("step {:>9}  pillars passed {:.2f}{}  {:.1f} steps/s{}  modes{}", step, done,
                 a.pillars > 0 ? fmt::format("/{}", a.pillars) : std::string(),
                 static_cast<double>(step - offset) / secs, eta, modes);
  };
  auto summary = [&] {
    for (int k = 0; k < cells.cell_count(); ++k)
      spdlog::info(
          "summary: cell {}  mode {}  columns {}  lateral shift per column {:.3f} um "
          "(d = {} um)  volume change {:+.3f} % (largest {:.3f} %)  deepest node in a wall or "
          "the pillar {:.3f} um",
          first + k, to_string(tracker.final_mode(k)), tracker.columns(k),
          tracker.shift_per_column(k), facts.row_shift_um,
          100 * (cells.volume(k) / v0[static_cast<std::size_t>(k)] - 1),
          100 * guard.worst_volume_change(k), guard.worst_penetration_um(k));
  };
  try {
    side.initialize();
    signal(SIGINT, on_sigint);
    spdlog::info("{} cells ({} nodes) of {}, connected", cells.cell_count(), cells.node_count(),
                 total);
    Points force;
    std::vector<double> u(static_cast<std::size_t>(3 * cells.node_count()));
    open_output();
    if (rows.empty()) sample(0);
    // The start, and on resume the checkpoint's step when its sample was lost with the previous
    // part file.
    if (mesh && offset % mesh_every == 0 &&
        (mesh->samples().empty() || mesh->samples().back().step < offset))
      sample_mesh(offset);
    std::int64_t s = offset;
    std::string reason = "step limit reached";
    // Wall time per step: membrane work (forces, moving the nodes) and the exchange, which includes
    // waiting for the fluid's step.
    double t_membrane = 0, t_exchange = 0;
    const std::int64_t s0 = s;
    const std::int64_t force_every = scene.coupling.force_every;
    for (; s < a.steps && !g_stop; ++s) {
      const auto t0 = Clock::now();
      // Time-scale separation ([coupling] force_every): between updates the last forces are held.
      if (s % force_every == 0 || s == s0) cells.compute_forces(force);
      const std::span<const double> f(force.data(), static_cast<std::size_t>(force.size()));
      const auto t1 = Clock::now();
      if (!side.advance(cells.flat_positions(), f, u)) {
        reason = "the fluid ended the run";
        break;
      }
      const auto t2 = Clock::now();
      cells.move(std::span<const double>(u), 1.0);
      t_membrane += std::chrono::duration<double>(t1 - t0 + (Clock::now() - t2)).count();
      t_exchange += std::chrono::duration<double>(t2 - t1).count();
      if (mesh_every > 0 && (s + 1) % mesh_every == 0) sample_mesh(s + 1);
      if ((s + 1) % a.sample_every == 0) {
        sample(s + 1);
        guard.check(cells, s + 1, first);
        if (a.pillars > 0 && tracker.min_columns() >= a.pillars) {
          reason = fmt::format("every cell passed {} pillars", a.pillars);
          ++s;
          break;
        }
        if (a.stop_when_mode_certain && tracker.all_modes_certain()) {
          reason = "every cell's mode is certain";
          ++s;
          break;
        }
      }
      if (a.checkpoint_every > 0 && (s + 1) % a.checkpoint_every == 0) checkpoint(s + 1);
      if ((s + 1) % scene.run.log_every == 0) progress(s + 1);
    }
    if (g_stop) reason = "interrupted";
    side.finalize();
    finish();
    checkpoint(s);
    spdlog::info("ran {} steps: {}", s, reason);
    if (s > s0)
      spdlog::info("time per step [ms]: membrane {:.3f}, exchange and fluid {:.3f}",
                   1e3 * t_membrane / static_cast<double>(s - s0),
                   1e3 * t_exchange / static_cast<double>(s - s0));
    summary();
    return 0;
  } catch (const coupler::CouplerError& e) {
    finish();
    spdlog::error("{}", e.what());
    return 3;
  } catch (const std::exception& e) {
    side.abort(e.what());
    finish();
    spdlog::error("{}", e.what());
    return 1;
  }
}

}  // namespace dld::membrane
