// SPDX-License-Identifier: MIT
// The typed, validated scene: what a scene file says, in physical units, plus the lattice values
// derived from it in one place (LatticeUnits). Sections read here: scene, geometry, lattice,
// fluid, drive, run, output. Tables owned by other programs (membrane, cells, coupling) are kept
// for them to read with the same strict TomlSection.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <string_view>

#include "shared/dld_geometry.hpp"
#include "shared/toml_section.hpp"
#include "shared/units.hpp"

namespace dld {

/// The collision operators, in the order of fluid/collision_registry.hpp (checked there).
enum class CollisionKind { kBgk, kTrt, kMrt };
inline constexpr std::array<std::string_view, 3> kCollisionNames{"bgk", "trt", "mrt"};

struct LatticeParams {
  double dx_um = 0.4;  ///< lattice spacing [um]
  double tau = 1.0;    ///< outer relaxation time [-]; nu_lu = (tau - 1/2)/3
  CollisionKind collision = CollisionKind::kTrt;
  double trt_magic = 3.0 / 16.0;  ///< TRT Lambda = (tau+ - 1/2)(tau- - 1/2) [-]
  bool curved_walls = false;      ///< pillar: Bouzidi interpolated bounce-back instead of half-way
};

struct FluidParams {
  double density_kg_m3 = 1025.0;   ///< plasma density [kg/m^3]
  double viscosity_Pa_s = 1.2e-3;  ///< outer (plasma) dynamic viscosity [Pa s]
  double viscosity_ratio = 1.0;    ///< inner / outer viscosity [-]
};

struct DriveParams {
  /// Driving body force density along x [Pa/m]; given directly or derived from `reynolds`.
  double pressure_gradient_Pa_per_m = 0.0;
  /// Target Re = U G / nu if the scene gave one; p' then comes from the plane-Poiseuille estimate
  /// U = p' H^2 / (12 mu), which overestimates U (the pillar slows the flow): the run reports the
  /// Re it actually reached.
  std::optional<double> reynolds;
  bool lateral_control = true;  ///< adjust a y body force so that the box-mean u_y stays zero
};

struct RunParams {
  std::int64_t max_steps = 10000;  ///< hard step limit
  double steady_tolerance = 0.0;   ///< stop when the relative change of mean u_x per
                                   ///< check (log_every steps) falls below this; 0 = off
  std::int64_t log_every = 500;    ///< steps between progress lines and time-series samples
  int threads = 0;                 ///< OpenMP threads; 0 = all cores
};

struct OutputParams {
  std::string file;                 ///< run HDF5 file; "" = runs/<scene name>.h5
  std::int64_t snapshot_every = 0;  ///< steps between field snapshots; 0 = final one only
  bool fields = true;               ///< write velocity/density snapshots at all
  /// Steps between samples of the membrane programs' node positions (their part files, with an
  /// XDMF beside them); 0 = none. Read here because [output] is this reader's table.
  std::int64_t mesh_every = 0;
};

/// How the fluid and the membrane programs are coupled ([coupling] table).
struct CouplingParams {
  std::string ib_kernel = "peskin4";  ///< immersed-boundary kernel: peskin2, peskin3, peskin4
  int membrane_processes = 1;         ///< cells are split among this many membrane programs
  std::string transport = "ipc";      ///< ipc (local processes) or tcp (see docs/protocol.md)
  double timeout_s = 30.0;            ///< a peer silent this long stops the run
  /// Time-scale separation (numerics, not physics; measured in docs/frontier.md): the membrane
  /// forces are recomputed every `force_every` steps and held in between (spread at the nodes'
  /// current positions every step unless spread_held), and the inside/outside viscosity field is
  /// rebuilt every `viscosity_field_every` steps, as HemoCell's timescale separation (Zavodszky et
  /// al., Front. Physiol. 8 (2017) 563). Steps are counted from the run's start, so a resumed run
  /// keeps the same update steps; 1 = every step (exact coupling).
  int force_every = 1;
  int viscosity_field_every = 1;
  /// With forces held (force_every > 1): also hold the force field spread from them, spread at
  /// the nodes' positions of the last force update instead of at the moved nodes every step
  /// (numerics: measured by configs/frontier/spread-held.toml, docs/performance.md "Held
  /// spreading"). No effect with force_every = 1.
  bool spread_held = false;
  /// With spread_held: also hold that spread's interpolation weights, so the nodes move by the
  /// velocity interpolated at their positions of the last force update (cheaper again, but the
  /// enclosed volumes drift faster: docs/performance.md, "Held spreading").
  bool interpolation_held = false;
  /// Every this many steps the membrane programs give each cell back the volume the immersed
  /// boundary let through since (membrane/volume_correction.hpp; numerics: the smallest node
  /// displacement that restores the rest volume); 0 = never. A multiple of force_every.
  std::int64_t volume_correction_every = 0;
  /// The steps at which both held quantities are updated: a run stopped and checkpointed at a
  /// multiple of this resumes exactly as the straight run goes on (elsewhere the resumed run would
  /// recompute what the straight one holds), so interrupted runs end at the next multiple.
  std::int64_t exact_resume_every() const {
    return std::lcm(std::lcm(static_cast<std::int64_t>(force_every),
                             static_cast<std::int64_t>(viscosity_field_every)),
                    held_resume_every);
  }
  /// Whether anything is held between steps (otherwise the coupling is exact).
  bool holds() const { return force_every > 1 || viscosity_field_every > 1; }
  /// Exact coupling (forces, viscosity field and spreading every step) for one invocation of the
  /// programs (dld-run --exact-coupling-for): the scene file, and the hash its checkpoints carry,
  /// stay as they are, and a held run continues from the checkpoint this one leaves. Interrupted,
  /// it still ends where the held coupling resumes exactly.
  void make_exact() {
    held_resume_every = exact_resume_every();
    force_every = viscosity_field_every = 1;
    spread_held = interpolation_held = false;
  }

 private:
  std::int64_t held_resume_every = 1;  ///< make_exact: the held coupling's exact_resume_every
};

struct Scene {
  std::string file;  ///< the scene file it came from
  std::string name;
  std::string description;
  DldCell cell_um;  ///< geometry in um
  LatticeParams lattice;
  FluidParams fluid;
  DriveParams drive;
  RunParams run;
  OutputParams output;
  CouplingParams coupling;
  std::string hash;  ///< FNV-1a of the file's bytes: both sides of a coupled run must match
  std::shared_ptr<TomlDocument> document;  ///< the parsed file, for the other programs' tables

  LatticeUnits units() const;
  /// Relaxation time inside the cells: nu_in = ratio nu_out with nu = (tau - 1/2)/3 [-].
  double tau_inner() const { return inner_relaxation_time(lattice.tau, fluid.viscosity_ratio); }
  /// Box size in nodes (whole numbers, checked at load).
  int nx() const;
  int ny() const;
  int nz() const;
  /// Geometry in lattice units (nodes).
  DldCell cell_lu() const { return cell_um.scaled(1.0 / lattice.dx_um); }
  /// Lattice body force density along x.
  double force_x_lu() const;
  /// Human-readable resolved scene: physical values and the lattice values chosen.
  std::string describe() const;
};

/// The reference setting of SPEC section 4 (dx = 0.4 um, tau = 1, Re = 0.1): moduli given "in
/// lattice units of the reference setting" (kappa_alpha = 0.5) are converted through it, so that
/// every other setting simulates the same dimensionless cell (SPEC section 9).
struct ReferenceSetting {
  static constexpr double kDxUm = 0.4;
  static constexpr double kTau = 1.0;
  static constexpr double kReynolds = 0.1;
};

/// Drive of a target Reynolds number Re = U G / nu by the plane-Poiseuille estimate
/// U = p' H^2 / (12 mu) [Pa/m] (the pillar slows the flow: the run reports the Re it reached).
double poiseuille_pressure_gradient(double reynolds, const DldCell& cell_um, const FluidParams& f);

/// Tables that the membrane program reads and checks itself.
inline const std::vector<std::string>& tables_owned_elsewhere() {
  static const std::vector<std::string> t{"membrane", "cells"};
  return t;
}

/// Reads and validates a scene file; throws InputError naming file, line and key.
/// With `check_unknown`, keys that no reader consumed (outside tables_owned_elsewhere()) are
/// errors.
Scene load_scene(const std::string& path, bool check_unknown = true);
/// The same from text (tests); `name` stands for the file in messages.
Scene parse_scene(std::string_view text, const std::string& name, bool check_unknown = true);

}  // namespace dld
