// SPDX-License-Identifier: MIT
#include "membrane/membrane_scene.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <filesystem>

#include "membrane/mesh_cache.hpp"

namespace dld::membrane {
namespace {

/// An array of strings (TomlSection has no getter for it): read from the document and mark read.
std::vector<std::string> strings(const Scene& scene, const TomlSection& s, std::string_view key) {
  const toml::node* n = scene.document->root().at_path(s.path() + "." + std::string(key)).node();
  if (!n) s.fail(key, "missing (required)");
  scene.document->mark_read(s.path() + "." + std::string(key));
  const toml::array* a = n->as_array();
  if (!a || a->empty()) s.fail(key, "expected a non-empty array of strings");
  std::vector<std::string> out;
  for (const auto& v : *a) {
    if (!v.is_string()) s.fail(key, "expected an array of strings");
    out.push_back(*v.value<std::string>());
  }
  return out;
}

/// kappa_s [N/m] from the one of capillary_number, kappa_s_N_per_m, shear_modulus_N_per_m given;
/// a capillary number is turned into kappa_s at the drive p' [Pa/m].
double shear_modulus(const Scene& scene, const TomlSection& m, double radius_um, double p) {
  const std::vector<std::string> keys{"capillary_number", "kappa_s_N_per_m",
                                      "shear_modulus_N_per_m"};
  int given = 0;
  for (const auto& k : keys) given += m.has(k) ? 1 : 0;
  if (given != 1)
    m.fail(given ? "capillary_number" : "kappa_s_N_per_m",
           "give exactly one of capillary_number, kappa_s_N_per_m and shear_modulus_N_per_m");
  if (m.has("kappa_s_N_per_m")) return m.positive("kappa_s_N_per_m");
  // Skalak law in Krueger's form has shear modulus G_s = kappa_s / 3.
  if (m.has("shear_modulus_N_per_m")) return 3.0 * m.positive("shear_modulus_N_per_m");
  const double cap = m.positive("capillary_number");
  if (!(p > 0.0))
    m.fail("capillary_number", "needs a positive drive pressure gradient (Ca = p' l r / kappa_s)");
  // SPEC section 4: Ca = p' l r / kappa_s with l = sqrt(G H).
  const double l = std::sqrt(scene.cell_um.gap() * scene.cell_um.depth) * 1e-6;
  return p * l * radius_um * 1e-6 / cap;
}

/// kappa_s of this cell in lattice units of the reference setting (SPEC 4: dx 0.4 um, tau 1,
/// Re 0.1): the same Ca there, or the same physical kappa_s where it was given directly. Moduli
/// given "in reference lattice units" are ratios to this, so they fix C = kappa_alpha / kappa_s
/// whatever this scene's dx, tau or Re (SPEC section 9).
double reference_shear_modulus_lu(const Scene& scene, const TomlSection& m, double radius_um) {
  const double p_ref =
      poiseuille_pressure_gradient(ReferenceSetting::kReynolds, scene.cell_um, scene.fluid);
  const LatticeUnits ref(ReferenceSetting::kDxUm * 1e-6, ReferenceSetting::kTau,
                         scene.fluid.viscosity_Pa_s / scene.fluid.density_kg_m3,
                         scene.fluid.density_kg_m3);
  return ref.modulus_lu(shear_modulus(scene, m, radius_um, p_ref));
}

/// [membrane] radius_um, shape_coefficients, mesh_faces, mesh_cache (the Evans-Fung shape).
void read_shape(const TomlSection& m, MembraneScene& out) {
  out.shape_um.radius = m.in_range("radius_um", 0.5, 20.0, 3.9);
  if (m.has("shape_coefficients")) {
    const auto c = m.numbers("shape_coefficients");
    if (c.size() != 3) m.fail("shape_coefficients", "expected three numbers [C0, C2, C4]");
    out.shape_um.c0 = c[0], out.shape_um.c2 = c[1], out.shape_um.c4 = c[2];
    for (int i = 0; i <= 100; ++i)
      if (!(out.shape_um.half_thickness(out.shape_um.radius * i / 101.0) > 0.0))
        m.fail("shape_coefficients",
               "the shape must have positive thickness everywhere inside the rim");
  }
  const auto faces = m.integer("mesh_faces", 2000);
  if (faces < 100 || faces > 50000)
    m.fail("mesh_faces", fmt::format("expected 100..50000, got {}", faces));
  out.mesh_faces = static_cast<int>(faces);
  out.mesh_cache = m.string("mesh_cache", default_mesh_cache_dir());
}

/// The reference mesh in lattice units, centred: a user's OFF file (lengths in um; it must pass
/// the same checks) or the Evans-Fung mesh.
void make_reference_mesh(const Scene& scene, const TomlSection& m, MembraneScene& out) {
  const double dx = scene.lattice.dx_um;
  if (m.has("mesh_file")) {
    if (m.has("mesh_faces") || m.has("shape_coefficients"))
      m.fail("mesh_file", "give either mesh_file or mesh_faces/shape_coefficients, not both");
    std::filesystem::path file(m.string("mesh_file"));
    if (file.is_relative()) file = std::filesystem::path(scene.file).parent_path() / file;
    out.reference_lu = read_off(file.string());
    validate_closed_surface(out.reference_lu, file.string());
    out.reference_lu.nodes /= dx;
    out.mesh_faces = out.reference_lu.face_count();
  } else {
    EvansFungShape shape_lu = out.shape_um;
    shape_lu.radius = out.radius_lu;
    out.reference_lu = evans_fung_mesh(shape_lu, out.mesh_faces, out.mesh_cache);
  }
  out.reference_lu.nodes.colwise() -= centroid(out.reference_lu.nodes);
}

/// [membrane] models and their tables.
void read_models(const Scene& scene, const TomlSection& m, MembraneScene& out) {
  const LatticeUnits units = scene.units();
  const ModelContext ctx{
      out.reference_lu,     out.kappa_s_lu,
      out.radius_lu,        reference_shear_modulus_lu(scene, m, out.shape_um.radius),
      units.energy_lu(1.0), m.has("capillary_number") ? m.positive("capillary_number") : 0.0};
  std::vector<std::string> names = strings(scene, m, "models");
  std::vector<AnyModel> models;
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j)
      if (names[j] == names[i])
        m.fail("models", fmt::format("model '{}' is listed twice", names[i]));
    models.push_back(make_model(names[i], m, "models", m.optional_section(names[i]), ctx));
  }
  out.mechanics = MembraneMechanics(names, std::move(models));
}

/// [membrane.contact]: range [um -> lattice], strength relative to kappa_s range^2.
void read_contact(const Scene& scene, const TomlSection& m, MembraneScene& out) {
  if (auto c = m.optional_section("contact")) {
    ContactParams p;
    p.range = c->positive("range_um") / scene.lattice.dx_um;
    p.strength = c->in_range("strength_rel", 0.0, 1e6) * out.kappa_s_lu * p.range * p.range;
    p.walls = c->boolean("walls", true);
    p.pillar = c->boolean("pillar", true);
    p.cells = c->boolean("cells", true);
    out.contact = p;
  }
}

/// [membrane.stretch] and [membrane.relax]: the standalone tasks (one at most).
void read_tasks(const TomlSection& m, MembraneScene& out) {
  if (auto s = m.optional_section("stretch")) {
    StretchTask t;
    t.forces_pN = s->numbers("forces_pN");
    if (t.forces_pN.empty()) s->fail("forces_pN", "expected at least one force");
    for (double f : t.forces_pN)
      if (!(f >= 0.0) || f > 1e4)
        s->fail("forces_pN", fmt::format("forces must be in [0, 1e4] pN, got {}", f));
    t.options.pulled_fraction = s->in_range("pulled_fraction", 0.001, 0.4, 0.05);
    t.options.solver.max_iterations = static_cast<int>(s->integer("max_iterations", 50000));
    // Converged when no node feels more than this fraction of kappa_s dx (a tiny force).
    t.options.solver.gradient_tolerance = s->positive("tolerance_rel", 1e-6) * out.kappa_s_lu;
    t.options.solver.max_step = 0.05;
    t.output_csv = s->string("output_csv", "");
    out.stretch = t;
  }
  if (auto r = m.optional_section("relax")) {
    RelaxTask t;
    t.initial_stretch = r->in_range("initial_stretch", 0.5, 2.0, 1.2);
    t.options.max_steps = static_cast<int>(r->integer("max_steps", 20000));
    if (t.options.max_steps < 1) r->fail("max_steps", "expected a positive integer");
    // Mobility scaled so that a force kappa_s dx moves a node by time_step * 1e-2 dx per step
    // at most; the step halves automatically if the energy would rise.
    t.options.mobility = 1.0 / out.kappa_s_lu;
    t.options.time_step = r->positive("time_step_rel", 0.05);
    t.options.force_tolerance = r->positive("tolerance_rel", 1e-6) * out.kappa_s_lu;
    out.relax = t;
  }
  if (out.stretch && out.relax)
    m.fail(
        "relax",
        "a scene runs one standalone task: give [membrane.stretch] or [membrane.relax], not both");
}

/// [cells] count (packed at random) or [[cells.cell]] (listed), and expected_mode.
void read_cells(const Scene& scene, const TomlSection& cells, MembraneScene& out) {
  const bool listed = !cells.sections("cell").empty();
  if (cells.has("count")) {
    if (listed)
      cells.fail("count", "give either count (cells packed at random) or [[cells.cell]], not both");
    PackRequest p;
    const auto count = cells.integer("count");
    if (count < 1 || count > 200)
      cells.fail("count", fmt::format("expected 1..200, got {}", count));
    p.count = static_cast<int>(count);
    const auto seed = cells.integer("seed", 1);
    if (seed < 0) cells.fail("seed", fmt::format("expected an integer >= 0, got {}", seed));
    p.seed = static_cast<std::uint64_t>(seed);
    p.cache = cells.string("packing_cache", default_packing_cache_dir());
    p.clearance_lu = out.contact ? out.contact->range : 1.0;
    out.pack = p;
  } else {
    for (const char* key : {"seed", "packing_cache"})
      if (cells.has(key)) cells.fail(key, "only used with count (cells packed at random)");
  }
  if (cells.has("expected_mode")) {
    // Spelled as to_string writes the modes: dld-analyze reads them back from the run file.
    const std::string zigzag = to_string(TransportMode::kZigzag);
    const std::string v =
        cells.choice("expected_mode", {zigzag, to_string(TransportMode::kDisplacement)});
    out.expected_mode = v == zigzag ? TransportMode::kZigzag : TransportMode::kDisplacement;
  }
  const double dx = scene.lattice.dx_um;
  for (const TomlSection& c : cells.sections("cell")) {
    const auto p = c.numbers("centre_um");
    if (p.size() != 3) c.fail("centre_um", "expected [x, y, z] in um");
    if (!std::isfinite(p[0] + p[1] + p[2])) c.fail("centre_um", "expected finite numbers (um)");
    out.centres_lu.emplace_back(p[0] / dx, p[1] / dx, p[2] / dx);
    const double angle = c.number("angle_deg", 0.0);
    if (!std::isfinite(angle)) c.fail("angle_deg", "expected a finite angle in degrees");
    out.angles_rad.push_back(angle * M_PI / 180.0);
    const DldCell box = scene.cell_um;
    if (p[2] < 0.0 || p[2] > box.depth) c.fail("centre_um", "z must lie between the walls");
    if (box.inside_pillar(p[0], p[1])) c.fail("centre_um", "the centre lies inside the pillar");
  }
}

}  // namespace

MembraneScene read_membrane_scene(const Scene& scene) {
  MembraneScene out;
  const TomlSection root = TomlSection::root(scene.document);
  const TomlSection m = root.section("membrane");
  read_shape(m, out);
  out.kappa_s_N_per_m =
      shear_modulus(scene, m, out.shape_um.radius, scene.drive.pressure_gradient_Pa_per_m);
  out.kappa_s_lu = scene.units().modulus_lu(out.kappa_s_N_per_m);
  out.radius_lu = out.shape_um.radius / scene.lattice.dx_um;
  make_reference_mesh(scene, m, out);
  read_models(scene, m, out);
  read_contact(scene, m, out);
  read_tasks(m, out);
  if (auto cells = root.optional_section("cells")) read_cells(scene, *cells, out);
  return out;
}

CellSet build_cells(const MembraneScene& m, const Scene& scene) {
  std::optional<Contact> contact;
  if (m.contact) contact.emplace(scene.cell_lu(), *m.contact);
  CellSet cells(m.reference_lu, m.mechanics, contact);
  for (std::size_t k = 0; k < m.centres_lu.size(); ++k)
    cells.add_cell(m.centres_lu[k], m.angles_rad[k]);
  if (m.pack) {
    const CachedPacking p = packed_scene_cells(m, scene);
    const int n = p.cells.nodes_per_cell;
    for (int k = 0; k < m.pack->count; ++k)
      cells.add_cell(Points(p.cells.positions.middleCols(Eigen::Index{k} * n, n)));
  }
  return cells;
}

CachedPacking packed_scene_cells(const MembraneScene& m, const Scene& scene, int count) {
  if (!m.pack && count < 1)
    throw InputError(fmt::format("{}: [cells] count is not set: nothing to pack", scene.file));
  PackOptions o;
  o.count = count > 0 ? count : m.pack->count;
  o.seed = m.pack ? m.pack->seed : 1;
  o.clearance = m.pack ? m.pack->clearance_lu : (m.contact ? m.contact->range : 1.0);
  const std::string cache = m.pack ? m.pack->cache : default_packing_cache_dir();
  CachedPacking p =
      packed_cells(m.reference_lu, scene.cell_lu(), o, cache,
                   [](const std::string& line) { spdlog::debug("packing: {}", line); });
  spdlog::info("{} {} cells (seed {}){}", p.from_cache ? "loaded" : "packed", o.count, o.seed,
               p.file.empty() ? std::string() : " : " + p.file);
  return p;
}

double haematocrit(const CellSet& cells, const DldCell& box) {
  double v = 0.0;
  for (int k = 0; k < cells.cell_count(); ++k) v += cells.volume(k);
  const double fluid = (box.lambda * box.lambda - M_PI * box.radius * box.radius) * box.depth;
  return v / fluid;
}

std::string MembraneScene::describe(const Scene& scene) const {
  const LatticeUnits u = scene.units();
  std::string s = fmt::format(
      "membrane: Evans-Fung r {} um ({:.4g} dx), C = ({}, {}, {}), {} faces requested, {} nodes/{} "
      "faces "
      "meshed\n",
      shape_um.radius, radius_lu, shape_um.c0, shape_um.c2, shape_um.c4, mesh_faces,
      reference_lu.node_count(), reference_lu.face_count());
  s += fmt::format(
      "  kappa_s {:.6g} N/m = {:.6g} lattice modulus; cell volume {:.6g} dx^3, area {:.6g} dx^2\n",
      kappa_s_N_per_m, kappa_s_lu, enclosed_volume(reference_lu), surface_area(reference_lu));
  for (const auto& model : mechanics.models()) s += "  " + membrane::describe(model) + "\n";
  if (contact)
    s += fmt::format(
        "  contact: range {:.4g} dx, eps {:.6g} lattice energy (walls {}, pillar {}, cells {})\n",
        contact->range, contact->strength, contact->walls, contact->pillar, contact->cells);
  const std::size_t count = pack ? static_cast<std::size_t>(pack->count) : centres_lu.size();
  s += fmt::format("  cells: {}{} ; force unit {:.6g} pN per lattice force", count,
                   pack ? fmt::format(" packed at random (seed {})", pack->seed) : "",
                   u.force_n(1.0) * 1e12);
  return s;
}

}  // namespace dld::membrane
