// SPDX-License-Identifier: MIT
#include "shared/scene.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace dld {
namespace {

/// "trt" -> "TRT", for the scene description.
std::string upper(std::string_view name) {
  std::string out(name);
  for (char& ch : out) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  return out;
}

/// Number of nodes along a length, required to be whole so walls and periodic boxes align.
int whole_nodes(const TomlSection& lattice, double length_um, double dx_um, const char* what) {
  double n = length_um / dx_um;
  long r = std::lround(n);
  if (r < 1 || std::abs(n - static_cast<double>(r)) > 1e-6 * n)
    lattice.fail("dx_um",
                 fmt::format("{} / dx = {:.4g} / {:.4g} = {:.4g} must be a whole number of "
                             "nodes (choose dx so that lambda/dx and H/dx are integers)",
                             what, length_um, dx_um, n));
  return static_cast<int>(r);
}

/// FNV-1a (64 bit) of the scene text, as 16 hex digits: the same file gives the same identity
/// on every machine and build. Its offset basis lacks the standard one's last digit
/// (14695981039346656037): still a fine checksum, and kept, since every checkpoint carries hashes
/// made with it; a tool that recomputes a scene's hash must use this one.
std::string fnv1a_hex(std::string_view text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

void read_geometry(const TomlSection& g, Scene& s) {
  s.cell_um.radius = g.positive("pillar_radius_um");
  s.cell_um.lambda = g.positive("pillar_spacing_um");
  s.cell_um.depth = g.positive("depth_um");
  s.cell_um.shift = g.number("row_shift_um");
  if (2.0 * s.cell_um.radius >= s.cell_um.lambda)
    g.fail("pillar_radius_um", fmt::format("pillar diameter {} um must be smaller than the pillar "
                                           "spacing {} um (the pillar would fill the box)",
                                           2.0 * s.cell_um.radius, s.cell_um.lambda));
  if (s.cell_um.shift < 0.0 || s.cell_um.shift >= s.cell_um.lambda)
    g.fail("row_shift_um", fmt::format("expected 0 <= d < lambda = {} um, got {}", s.cell_um.lambda,
                                       s.cell_um.shift));
}

void read_lattice(const TomlSection& l, Scene& s) {
  s.lattice.dx_um = l.positive("dx_um");
  s.lattice.tau = l.number("tau", 1.0);
  if (!(s.lattice.tau > 0.5))
    l.fail("tau",
           fmt::format("relaxation time must be > 1/2 (viscosity > 0), got {}", s.lattice.tau));
  const std::vector<std::string> names(kCollisionNames.begin(), kCollisionNames.end());
  const std::string collision = l.choice("collision", names, "trt");
  for (std::size_t k = 0; k < names.size(); ++k)
    if (names[k] == collision) s.lattice.collision = static_cast<CollisionKind>(k);
  s.lattice.trt_magic = l.positive("trt_magic", 3.0 / 16.0);
  s.lattice.curved_walls =
      l.choice("wall_rule", {"bounce_back", "bouzidi"}, "bounce_back") == "bouzidi";
  whole_nodes(l, s.cell_um.lambda, s.lattice.dx_um, "pillar spacing lambda");
  int nz = whole_nodes(l, s.cell_um.depth, s.lattice.dx_um, "depth H");
  if (nz < 2) l.fail("dx_um", "the depth must span at least 2 nodes");
  double gap_nodes = s.cell_um.gap() / s.lattice.dx_um;
  if (gap_nodes < 2.0)
    l.fail("dx_um", fmt::format("the gap G = {} um spans only {:.2g} nodes; need at least 2",
                                s.cell_um.gap(), gap_nodes));
}

void read_fluid(const TomlSection& f, Scene& s) {
  s.fluid.density_kg_m3 = f.positive("density_kg_m3", s.fluid.density_kg_m3);
  s.fluid.viscosity_Pa_s = f.positive("viscosity_Pa_s", s.fluid.viscosity_Pa_s);
  s.fluid.viscosity_ratio = f.positive("viscosity_ratio", 1.0);
  const double tau_in = s.tau_inner();
  if (tau_in > 20.0)
    f.fail("viscosity_ratio",
           fmt::format("inner relaxation time {} is too large to be accurate", tau_in));
}

/// [drive]: exactly one of reynolds and pressure_gradient_Pa_per_m; then the Mach check of the
/// plane-Poiseuille speed estimate (it needs the lattice and the fluid).
void read_drive(const TomlSection& d, Scene& s) {
  const bool has_re = d.has("reynolds");
  const bool has_p = d.has("pressure_gradient_Pa_per_m");
  if (has_re == has_p)
    d.fail(has_re ? "reynolds" : "pressure_gradient_Pa_per_m",
           "give exactly one of drive.reynolds and drive.pressure_gradient_Pa_per_m");
  if (has_re) {
    double re = d.positive("reynolds");
    if (re > 10.0)
      d.fail("reynolds", fmt::format("expected Re <= 10 (Stokes-like flow), got {}", re));
    s.drive.reynolds = re;
    s.drive.pressure_gradient_Pa_per_m = poiseuille_pressure_gradient(re, s.cell_um, s.fluid);
  } else {
    s.drive.pressure_gradient_Pa_per_m = d.number("pressure_gradient_Pa_per_m");
    if (s.drive.pressure_gradient_Pa_per_m < 0.0)
      d.fail("pressure_gradient_Pa_per_m", "expected >= 0 (flow along +x)");
  }
  s.drive.lateral_control = d.boolean("lateral_control", true);
}

void check_mach(const TomlSection& d, const Scene& s) {
  // Lattice velocity check: keep Mach number small so compressibility errors stay negligible.
  const double mu = s.fluid.viscosity_Pa_s;
  const double h = s.cell_um.depth * 1e-6;
  LatticeUnits u = s.units();
  double u_lu = u.velocity_lu(s.drive.pressure_gradient_Pa_per_m * h * h / (12.0 * mu));
  if (u_lu > 0.05)
    d.fail(s.drive.reynolds ? "reynolds" : "pressure_gradient_Pa_per_m",
           fmt::format("the estimated lattice velocity {:.3g} exceeds 0.05 (Mach too high); lower "
                       "the drive or raise tau",
                       u_lu));
}

void read_run(const TomlSection& r, Scene& s) {
  s.run.max_steps = r.integer("max_steps", s.run.max_steps);
  if (s.run.max_steps < 1) r.fail("max_steps", "expected a positive integer");
  s.run.steady_tolerance = r.in_range("steady_tolerance", 0.0, 1.0, 0.0);
  s.run.log_every = r.integer("log_every", s.run.log_every);
  if (s.run.log_every < 1) r.fail("log_every", "expected a positive integer");
  std::int64_t th = r.integer("threads", 0);
  if (th < 0 || th > 1024) r.fail("threads", "expected 0 (all cores) or a thread count");
  s.run.threads = static_cast<int>(th);
}

void read_output(const TomlSection& o, Scene& s) {
  s.output.file = o.string("file", "");
  s.output.snapshot_every = o.integer("snapshot_every", 0);
  if (s.output.snapshot_every < 0) o.fail("snapshot_every", "expected >= 0");
  s.output.fields = o.boolean("fields", true);
  s.output.mesh_every = o.integer("mesh_every", 0);
  if (s.output.mesh_every < 0)
    o.fail("mesh_every", "expected steps between mesh samples >= 0 (0: no meshes)");
}

void read_coupling(const TomlSection& c, Scene& s) {
  s.coupling.ib_kernel = c.choice("ib_kernel", {"peskin2", "peskin3", "peskin4"}, "peskin4");
  const std::int64_t k = c.integer("membrane_processes", 1);
  if (k < 1 || k > 64) c.fail("membrane_processes", "expected 1 to 64 membrane processes");
  s.coupling.membrane_processes = static_cast<int>(k);
  s.coupling.transport = c.choice("transport", {"ipc", "tcp"}, "ipc");
  s.coupling.timeout_s = c.in_range("timeout_s", 0.1, 86400.0, 30.0);
  auto every = [&](const char* key, const char* what) {
    const std::int64_t n = c.integer(key, 1);
    if (n < 1 || n > 1000)
      c.fail(key, fmt::format("expected 1 to 1000 steps between {} (1: every step)", what));
    return static_cast<int>(n);
  };
  s.coupling.force_every = every("force_every", "membrane force updates");
  s.coupling.viscosity_field_every =
      every("viscosity_field_every", "rebuilds of the viscosity field");
  s.coupling.spread_held = c.boolean("spread_held", false);
  s.coupling.interpolation_held = c.boolean("interpolation_held", false);
  if (s.coupling.interpolation_held && !s.coupling.spread_held)
    c.fail("interpolation_held", "needs spread_held = true (the weights held are the spread's)");
  s.coupling.volume_correction_every = c.integer("volume_correction_every", 0);
  if (s.coupling.volume_correction_every < 0 || s.coupling.volume_correction_every > 1000000 ||
      s.coupling.volume_correction_every % s.coupling.force_every != 0)
    c.fail("volume_correction_every",
           fmt::format("expected 0 (never) or a multiple of force_every ({}) up to 1000000 steps",
                       s.coupling.force_every));
}

Scene read(const std::shared_ptr<TomlDocument>& doc, bool check_unknown, std::string_view text) {
  Scene s;
  s.hash = fnv1a_hex(text);
  s.file = doc->file();
  s.document = doc;
  TomlSection root = TomlSection::root(doc);

  TomlSection meta = root.section("scene");
  s.name = meta.string("name");
  if (s.name.empty() || s.name.find('/') != std::string::npos)
    meta.fail("name", "expected a non-empty name without '/'");
  s.description = meta.string("description", "");

  read_geometry(root.section("geometry"), s);
  read_lattice(root.section("lattice"), s);
  if (auto f = root.optional_section("fluid")) read_fluid(*f, s);
  const TomlSection d = root.section("drive");
  read_drive(d, s);
  if (auto r = root.optional_section("run")) read_run(*r, s);
  if (auto o = root.optional_section("output")) read_output(*o, s);
  if (s.output.file.empty()) s.output.file = "runs/" + s.name + ".h5";
  if (auto c = root.optional_section("coupling")) read_coupling(*c, s);
  check_mach(d, s);

  if (check_unknown) doc->reject_unknown(tables_owned_elsewhere());
  return s;
}

}  // namespace

double poiseuille_pressure_gradient(double reynolds, const DldCell& cell_um, const FluidParams& f) {
  const double nu = f.viscosity_Pa_s / f.density_kg_m3;
  const double h = cell_um.depth * 1e-6;
  const double u = reynolds * nu / (cell_um.gap() * 1e-6);
  return 12.0 * f.viscosity_Pa_s * u / (h * h);
}

LatticeUnits Scene::units() const {
  return LatticeUnits(lattice.dx_um * 1e-6, lattice.tau, fluid.viscosity_Pa_s / fluid.density_kg_m3,
                      fluid.density_kg_m3);
}

int Scene::nx() const {
  return static_cast<int>(std::lround(cell_um.lambda / lattice.dx_um));
}
int Scene::ny() const {
  return nx();
}
int Scene::nz() const {
  return static_cast<int>(std::lround(cell_um.depth / lattice.dx_um));
}

double Scene::force_x_lu() const {
  return units().force_density_lu(drive.pressure_gradient_Pa_per_m);
}

std::string Scene::describe() const {
  LatticeUnits u = units();
  DldCell c = cell_lu();
  std::string out;
  out += fmt::format("scene '{}' ({})\n", name, file);
  out += fmt::format(
      "  geometry: lambda {} um, R {} um, G {} um, H {} um, d {} um (eps = d/lambda = {:.5g})\n",
      cell_um.lambda, cell_um.radius, cell_um.gap(), cell_um.depth, cell_um.shift,
      cell_um.shift / cell_um.lambda);
  out += fmt::format("  fluid: rho {} kg/m^3, mu {} Pa s, nu {:.4g} m^2/s, viscosity ratio {}\n",
                     fluid.density_kg_m3, fluid.viscosity_Pa_s,
                     fluid.viscosity_Pa_s / fluid.density_kg_m3, fluid.viscosity_ratio);
  out += fmt::format(
      "  drive: p' = {:.6g} Pa/m{}\n", drive.pressure_gradient_Pa_per_m,
      drive.reynolds
          ? fmt::format(" (from target Re = {} by the plane-Poiseuille estimate)", *drive.reynolds)
          : std::string());
  out += fmt::format(
      "  lattice: dx {} um, dt {:.6g} s, tau {}{} ({}{}), nu_lu {:.6g}\n", lattice.dx_um, u.dt_s(),
      lattice.tau,
      fluid.viscosity_ratio != 1.0 ? fmt::format(" outside, {:.6g} inside the cells", tau_inner())
                                   : std::string(),
      upper(kCollisionNames[static_cast<std::size_t>(lattice.collision)]),
      lattice.collision != CollisionKind::kBgk ? fmt::format(", Lambda {:.6g}", lattice.trt_magic)
                                               : std::string(),
      u.nu_lu());
  out += fmt::format(
      "  lattice box: {} x {} x {} nodes, R {:.4g}, G {:.4g}, d {:.4g} nodes; pillar wall: {}\n",
      nx(), ny(), nz(), c.radius, c.gap(), c.shift,
      lattice.curved_walls ? "Bouzidi interpolated bounce-back" : "half-way bounce-back");
  out += fmt::format("  lattice body force: f_x {:.6g} (lattice units)", force_x_lu());
  out += fmt::format(
      "\n  coupling: {} kernel, membrane forces every {} step(s){}, viscosity field every {} "
      "step(s)",
      coupling.ib_kernel, coupling.force_every,
      !coupling.spread_held || coupling.force_every == 1 ? ""
      : coupling.interpolation_held ? " (spread and its weights held with them)"
                                    : " (spread held with them)",
      coupling.viscosity_field_every);
  if (coupling.volume_correction_every > 0)
    out += fmt::format(", cell volumes restored every {} steps", coupling.volume_correction_every);
  return out;
}

Scene load_scene(const std::string& path, bool check_unknown) {
  auto doc = TomlDocument::load(path);  // reports a missing or unreadable file by name
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return read(doc, check_unknown, text.str());
}

Scene parse_scene(std::string_view text, const std::string& name, bool check_unknown) {
  return read(TomlDocument::parse(text, name), check_unknown, text);
}

}  // namespace dld
