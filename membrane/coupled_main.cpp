// SPDX-License-Identifier: MIT
// The coupled mode of dld-membrane: the cells of this process (an equal share of the scene's
// [[cells.cell]] list) exchange positions and forces for velocities with dld-fluid every step,
// and move with the fluid (no-slip: X += U dt, dt = 1 in lattice units).
// Output: per-cell centroid (device frame, um: cells are never folded into the box) and volume
// every `sample_every` steps, written when the run ends or fails.
#include "membrane/coupled_main.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <vector>

#include "coupler/endpoint.hpp"
#include "coupler/error.hpp"
#include "coupler/membrane_side.hpp"
#include "coupler/scene_identity.hpp"
#include "shared/h5file.hpp"

namespace dld::membrane {
namespace {

volatile sig_atomic_t g_stop = 0;
void on_sigint(int) {
  g_stop = 1;
}

void write_samples(const std::string& path, const std::vector<double>& rows, int cells,
                   int first_cell, double dt_s) {
  std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  H5File f(path, H5File::Mode::kCreate);
  const std::uint64_t width = 1 + 4 * static_cast<std::uint64_t>(cells);
  f.write("/cells/samples", rows.data(), {rows.size() / width, width});
  f.attribute("/cells/samples", "columns",
              std::string("step, then per cell: centroid x y z [um, device frame], volume [um^3]"));
  f.attribute("/cells", "count", static_cast<std::int64_t>(cells));
  f.attribute("/cells", "first_cell", static_cast<std::int64_t>(first_cell));
  f.attribute("/cells", "dt_s", dt_s);
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

  const double dx_um = scene.lattice.dx_um;
  std::vector<double> rows;
  auto sample = [&](std::int64_t step) {
    rows.push_back(static_cast<double>(step));
    for (int k = 0; k < cells.cell_count(); ++k) {
      const Eigen::Vector3d c = cells.centroid(k);
      rows.insert(rows.end(), {c.x() * dx_um, c.y() * dx_um, c.z() * dx_um,
                               cells.volume(k) * dx_um * dx_um * dx_um});
    }
  };
  auto finish = [&] {
    if (!a.output.empty())
      write_samples(a.output, rows, cells.cell_count(), first, scene.units().dt_s());
  };
  try {
    side.initialize();
    signal(SIGINT, on_sigint);
    spdlog::info("{} cells ({} nodes) of {}, connected", cells.cell_count(), cells.node_count(),
                 total);
    Points force;
    std::vector<double> u(static_cast<std::size_t>(3 * cells.node_count()));
    sample(0);
    std::int64_t s = 0;
    for (; s < a.steps && !g_stop; ++s) {
      cells.compute_forces(force);
      const std::span<const double> f(force.data(), static_cast<std::size_t>(force.size()));
      if (!side.advance(cells.flat_positions(), f, u)) break;
      cells.move(std::span<const double>(u), 1.0);
      if ((s + 1) % a.sample_every == 0) {
        sample(s + 1);
        for (int k = 0; k < cells.cell_count(); ++k) {
          const double v = cells.volume(k);
          if (!std::isfinite(v) || !cells.centroid(k).allFinite())
            throw std::runtime_error(
                fmt::format("cell {} became non-finite at step {}", first + k, s + 1));
          if (std::abs(v / v0[static_cast<std::size_t>(k)] - 1.0) > 0.05)
            throw std::runtime_error(
                fmt::format("cell {} volume changed by {:+.1f} % at step {} (unstable)", first + k,
                            100 * (v / v0[static_cast<std::size_t>(k)] - 1), s + 1));
        }
      }
    }
    side.finalize();
    finish();
    spdlog::info("ran {} steps", s);
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
