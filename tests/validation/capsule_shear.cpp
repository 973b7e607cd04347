// SPDX-License-Identifier: MIT
#include "capsule_shear.hpp"

#include <fmt/format.h>
#include <stdlib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <thread>
#include <zmq.hpp>

#include "coupler/fluid_side.hpp"
#include "coupler/membrane_side.hpp"
#include "fluid/collision.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/immersed_boundary.hpp"
#include "fluid/viscosity_contrast.hpp"
#include "membrane/cell_set.hpp"
#include "membrane/sphere_mesh.hpp"
#include "membrane/taylor_deformation.hpp"
#include "shared/units.hpp"
#include "tests/temp_dir.hpp"

namespace dld::validation {

Transport transport_from_name(const std::string& name) {
  if (name == "inproc") return Transport::inproc;
  if (name == "ipc") return Transport::ipc;
  if (name == "tcp") return Transport::tcp;
  throw std::invalid_argument("transport must be inproc, ipc or tcp, got '" + name + "'");
}

std::string name(Transport t) {
  return t == Transport::inproc ? "inproc" : t == Transport::ipc ? "ipc" : "tcp";
}

double shear_modulus_for(double capillary, double mu, double gammadot, double radius) {
  return mu * gammadot * radius / (3.0 * capillary);
}

double mean_deformation(const CapsuleShearRun& run, double from) {
  double sum = 0;
  int n = 0;
  for (std::size_t i = 0; i < run.strain.size(); ++i)
    if (run.strain[i] >= from) {
      sum += run.deformation[i];
      ++n;
    }
  if (n == 0) throw std::runtime_error(fmt::format("no samples after gammadot t = {}", from));
  return sum / n;
}

namespace {

/// A fresh directory for ipc sockets, removed when the run ends.
struct SocketDir : dld::test::TempDir {
  SocketDir() : dld::test::TempDir("dld-capsule") {}
};

std::string fluid_endpoint(Transport t, const SocketDir& dir) {
  static std::atomic<int> counter{0};
  switch (t) {
    case Transport::inproc:
      return fmt::format("inproc://capsule-shear-{}", counter++);
    case Transport::ipc:
      return fmt::format("ipc://{}/fluid", dir.path().string());
    case Transport::tcp:
      return "tcp://127.0.0.1:*";  // the system picks the port
  }
  return {};
}

/// Both sides agree on this identity: the box's size and the capsule (lattice units).
coupler::SceneIdentity identity(const CapsuleShearSetup& s) {
  coupler::SceneIdentity id;
  id.scene_hash = fmt::format("capsule-shear a={} box={}x{}x{} Ca={} Re={}", s.radius, s.nx, s.ny,
                              s.nz, s.capillary, s.reynolds);
  id.agreed = {{"nx", static_cast<double>(s.nx), 0.0},
               {"ny", static_cast<double>(s.ny), 0.0},
               {"nz", static_cast<double>(s.nz), 0.0},
               {"radius_lu", s.radius, 1e-12}};
  id.total_cells = 1;
  return id;
}

coupler::Options options() {
  coupler::Options o;
  o.timeout = std::chrono::milliseconds(120'000);  // runs are niced on a shared machine
  o.handshake_timeout = std::chrono::milliseconds(120'000);
  return o;
}

/// Populations at equilibrium with the undisturbed shear u_x = gammadot (z - nz/2), so the run
/// starts in developed simple shear (as the reference does) instead of spinning up for nz^2/nu.
void start_in_shear(fluid::FluidSolver& solver, double gammadot) {
  const auto& L = solver.lattice();
  const std::size_t n = L.padded_size();
  double* f = solver.populations();
  for (int k = 0; k < L.nz(); ++k)
    for (int j = 0; j < L.ny(); ++j)
      for (int i = 0; i < L.nx(); ++i) {
        const std::size_t s = L.index(i, j, k);
        const double ux = gammadot * (k + 0.5 - 0.5 * L.nz());
        for (int q = 0; q < fluid::D3Q19::q; ++q)
          f[q * n + s] = fluid::equilibrium(q, 1.0, ux, 0.0, 0.0);
      }
}

membrane::MembraneMechanics mechanics(const CapsuleShearSetup& s, const membrane::TriMesh& mesh,
                                      double shear_modulus) {
  if (s.law == MembraneLaw::neo_hookean)
    return {{"neo_hookean"}, {membrane::NeoHookeanModel(mesh, {shear_modulus})}};
  // Skalak in Krueger's form: G_s = kappa_s / 3, C = kappa_alpha / kappa_s (skalak_model.hpp).
  const double kappa_s = 3.0 * shear_modulus;
  return {{"skalak"}, {membrane::SkalakModel(mesh, {kappa_s, s.skalak_c * kappa_s})}};
}

}  // namespace

CapsuleShearRun run_capsule_shear(const CapsuleShearSetup& s) {
  const double nu = (s.tau - 0.5) / 3.0;
  const double mu = nu;  // rho0 = 1
  CapsuleShearRun run;
  run.gammadot = s.reynolds * nu / (s.radius * s.radius);
  run.wall_speed = 0.5 * run.gammadot * s.nz;
  run.shear_modulus = shear_modulus_for(s.capillary, mu, run.gammadot, s.radius);
  run.steps = s.steps > 0 ? s.steps : static_cast<std::int64_t>(std::ceil(s.strain / run.gammadot));

  fluid::FluidConfig fc;
  fc.domain.nx = s.nx;
  fc.domain.ny = s.ny;
  fc.domain.nz = s.nz;
  fc.domain.walls_z = true;
  fc.domain.wall_velocity_low = {-run.wall_speed, 0, 0};
  fc.domain.wall_velocity_high = {run.wall_speed, 0, 0};
  fc.collision = s.collision;
  fc.tau = s.tau;
  fluid::FluidSolver solver(fc);
  start_in_shear(solver, run.gammadot);
  const fluid::ImmersedBoundary ib(solver.lattice(), s.kernel);

  const membrane::TriMesh mesh =
      membrane::icosphere(membrane::icosphere_subdivisions(s.faces), s.radius);
  membrane::CellSet cells(mesh, mechanics(s, mesh, run.shear_modulus));
  cells.add_cell(Eigen::Vector3d(0.5 * s.nx, 0.5 * s.ny, 0.5 * s.nz));
  run.nodes = cells.node_count();
  run.faces = mesh.face_count();
  const double volume0 = cells.volume(0);

  SocketDir dir;
  zmq::context_t context;
  const coupler::SceneIdentity id = identity(s);
  coupler::FluidSide fluid_side({id, {fluid_endpoint(s.transport, dir)}, {}, options()}, context);
  const std::string endpoint = fluid_side.endpoints()[0];
  std::string fluid_error, membrane_error;
  const auto start = std::chrono::steady_clock::now();

  std::thread fluid_thread([&] {
    try {
      fluid_side.initialize();
      // The contrast is built from the triangles the membrane sent in its hello (protocol v2),
      // as dld-fluid does.
      std::unique_ptr<fluid::ViscosityContrast> contrast;
      if (s.viscosity_ratio != 1.0) {
        contrast = std::make_unique<fluid::ViscosityContrast>(
            solver.lattice(), s.tau, inner_relaxation_time(s.tau, s.viscosity_ratio),
            fluid_side.cell_nodes(), fluid_side.cell_faces(), fluid_side.faces());
        run.inside_min = 1e300;
      }
      std::vector<double> velocity;
      const std::size_t n = solver.lattice().padded_size();
      while (fluid_side.receive()) {
        const auto x = fluid_side.positions();
        const auto f = fluid_side.forces();
        const auto field = solver.force_field();
        const bool spread =
            !s.spread_held || fluid_side.step() % static_cast<std::uint64_t>(s.force_every) == 0;
        if (spread) ib.spread(x, f, field);
        if (contrast) {
          contrast->update(x, solver.relaxation_field());
          const double inside = static_cast<double>(contrast->inside_nodes().size()) / volume0;
          run.inside_min = std::min(run.inside_min, inside);
          run.inside_max = std::max(run.inside_max, inside);
        }
        if (fluid_side.step() % static_cast<std::uint64_t>(s.sample_every) == 0) {
          for (int c = 0; c < 3; ++c) {
            double on_lattice = 0, on_markers = 0, magnitude = 0;
            for (std::size_t i = 0; i < n; ++i) on_lattice += field[c][i];
            for (std::size_t i = c; i < f.size(); i += 3) {
              on_markers += f[i];
              magnitude += std::abs(f[i]);
            }
            if (magnitude > 0) {
              run.spread_error =
                  std::max(run.spread_error, std::abs(on_lattice - on_markers) / magnitude);
              run.net_force = std::max(run.net_force, std::abs(on_markers) / magnitude);
            }
          }
        }
        solver.step();
        velocity.resize(x.size());
        if (!spread && s.interpolation_held) {
          ib.interpolate_at_spread(solver.velocity_field(), velocity);
        } else {
          ib.interpolate(x, solver.velocity_field(), velocity);
        }
        fluid_side.send_velocities(velocity);
      }
      fluid_side.finalize();
    } catch (const std::exception& e) {
      fluid_error = e.what();
      fluid_side.abort(e.what());
    }
  });

  std::thread membrane_thread([&] {
    std::unique_ptr<coupler::MembraneSide> owned;
    try {
      owned = std::make_unique<coupler::MembraneSide>(
          coupler::MembraneConfig{
              id, endpoint, "capsule", 0, 1, 0, {static_cast<std::uint32_t>(run.nodes)}, options()},
          context);
      auto& side = *owned;
      side.set_cell_surfaces({static_cast<std::uint32_t>(run.faces)}, membrane::face_indices(mesh));
      side.initialize();
      membrane::Points force;
      std::vector<double> velocity(3 * static_cast<std::size_t>(run.nodes));
      auto sample = [&](std::int64_t step) {
        const auto shape =
            membrane::shear_plane_shape(membrane::inertia_ellipsoid(mesh, cells.positions()),
                                        Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY());
        run.strain.push_back(run.gammadot * static_cast<double>(step));
        run.deformation.push_back(shape.deformation);
        run.inclination.push_back(shape.inclination);
        run.volume.push_back(cells.volume(0) / volume0);
      };
      for (std::int64_t step = 0; step < run.steps; ++step) {
        if (step % s.sample_every == 0) sample(step);
        if (step % s.force_every == 0) cells.compute_forces(force);
        if (!side.advance(cells.flat_positions(),
                          {force.data(), static_cast<std::size_t>(force.size())}, velocity))
          throw std::runtime_error(fmt::format("the fluid ended the run at step {}", step));
        cells.move(velocity, 1.0);  // X(n+1) = X(n) + U(n) dt, dt = 1
        if (!cells.positions().allFinite())
          throw std::runtime_error(fmt::format("membrane diverged at step {}", step));
      }
      sample(run.steps);
      side.finalize();
    } catch (const std::exception& e) {
      membrane_error = e.what();
      if (owned) owned->abort(e.what());  // the fluid stops too instead of waiting for a step
    }
  });
  membrane_thread.join();
  fluid_thread.join();
  run.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!fluid_error.empty() || !membrane_error.empty())
    throw std::runtime_error(fmt::format("capsule in shear over {}: fluid: '{}', membrane: '{}'",
                                         name(s.transport), fluid_error, membrane_error));
  run.nodes_final = cells.positions();
  return run;
}

}  // namespace dld::validation
