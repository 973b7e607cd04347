// SPDX-License-Identifier: MIT
// SPEC section 9: a setting of the study (coarse, medium, the reference) changes the numerics and
// never the cell. Every run of configs/study/study.toml, at every setting, is read as the
// membrane program reads it, and its dimensionless cell is compared with the reference setting's
// run of the same coordinates: C = kappa_alpha / kappa_s, kappa_b / (kappa_s r^2),
// kappa_V r / kappa_s, the contact range and strength relative to r and kappa_s r^2, the
// viscosity ratio and Ca.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <variant>

#include "coupler/launcher/study.hpp"
#include "membrane/membrane_scene.hpp"
#include "shared/scene.hpp"

namespace {

namespace fs = std::filesystem;
using dld::membrane::MembraneScene;

struct Cell {
  double kappa_alpha_lu = 0;  ///< not dimensionless: checked at the reference setting only
  double ca = 0, area_ratio = 0, bending = 0, volume = 0, contact_range = 0, contact_strength = 0,
         viscosity_ratio = 0;
};

Cell dimensionless_cell(const dld::Scene& scene, const MembraneScene& m) {
  Cell c;
  const double ks = m.kappa_s_lu, r = m.radius_lu;
  c.ca = scene.drive.pressure_gradient_Pa_per_m *
         std::sqrt(scene.cell_um.gap() * scene.cell_um.depth) * 1e-6 * m.shape_um.radius * 1e-6 /
         m.kappa_s_N_per_m;
  for (const auto& model : m.mechanics.models()) {
    if (const auto* s = std::get_if<dld::membrane::SkalakModel>(&model))
      c.kappa_alpha_lu = s->law().p.kappa_alpha, c.area_ratio = c.kappa_alpha_lu / ks;
    if (const auto* b = std::get_if<dld::membrane::BendingModel>(&model))
      c.bending = b->params().kappa_b / (ks * r * r);
    if (const auto* v = std::get_if<dld::membrane::VolumePenalty>(&model))
      c.volume = v->params().kappa_v * r / ks;
  }
  if (m.contact) {
    c.contact_range = m.contact->range / r;
    c.contact_strength = m.contact->strength / (ks * r * r);
  }
  c.viscosity_ratio = scene.fluid.viscosity_ratio;
  return c;
}

void expect_same(double setting, double reference, const std::string& what) {
  EXPECT_NEAR(setting, reference, 1e-10 * std::abs(reference)) << what;
}

TEST(StudyCell, EverySettingSimulatesTheSameCell) {
  const fs::path cache = fs::temp_directory_path() / ("dld-study-cell-" + std::to_string(getpid()));
  const auto study =
      dld::coupler::load_study(std::string(DLD_SOURCE_DIR) + "/configs/study/study.toml");
  std::map<std::string, Cell> reference;  // run name -> cell at the reference setting
  std::vector<std::string> settings{""};  // "" = the study's own (reference) setting
  for (const auto& [name, table] : study.resolutions) settings.push_back(name);
  ASSERT_GE(settings.size(), 3u) << "the study file should name the coarse and medium settings";
  for (const std::string& setting : settings) {
    for (dld::coupler::StudyRun& run : study.runs(setting)) {
      // Only the first Ht of each (d, Ca): the cell does not depend on the cell count.
      if (run.coordinates[0] != study.axes[0].values[0]) continue;
      run.scene["membrane"].as_table()->insert_or_assign("mesh_cache", cache.string());
      const dld::Scene scene = dld::parse_scene(dld::coupler::scene_text(run), run.name);
      const Cell c = dimensionless_cell(scene, dld::membrane::read_membrane_scene(scene));
      if (setting.empty()) {
        reference[run.name] = c;
        // SPEC 4 at the reference setting: kappa_alpha 0.5 lattice units, kappa_b 2.5e-3 ks r^2.
        EXPECT_EQ(scene.lattice.dx_um, dld::ReferenceSetting::kDxUm);
        EXPECT_EQ(scene.lattice.tau, dld::ReferenceSetting::kTau);
        EXPECT_EQ(*scene.drive.reynolds, dld::ReferenceSetting::kReynolds);
        expect_same(c.kappa_alpha_lu, 0.5, run.name + ": kappa_alpha at the reference setting");
        expect_same(c.area_ratio, 350.28306389557434 * c.ca, run.name + ": C = 350.283 Ca");
        expect_same(c.bending, 2.5e-3, run.name + ": bending");
        continue;
      }
      ASSERT_TRUE(reference.count(run.name)) << run.name;
      const Cell& ref = reference[run.name];
      const std::string where = run.name + " at " + setting + ": ";
      expect_same(c.ca, ref.ca, where + "Ca");
      expect_same(c.area_ratio, ref.area_ratio, where + "C = kappa_alpha / kappa_s");
      expect_same(c.bending, ref.bending, where + "kappa_b / (kappa_s r^2)");
      expect_same(c.volume, ref.volume, where + "kappa_V r / kappa_s");
      expect_same(c.contact_range, ref.contact_range, where + "contact range / r");
      expect_same(c.contact_strength, ref.contact_strength, where + "contact strength");
      expect_same(c.viscosity_ratio, ref.viscosity_ratio, where + "viscosity ratio");
    }
  }
  fs::remove_all(cache);
  EXPECT_EQ(reference.size(), study.axes[1].values.size() * study.axes[2].values.size());
}

// The key area_modulus_ref_lu (single-cell and dilute-map scenes) gives the C that the study file
// writes out, at any lattice, tau and Reynolds number.
TEST(StudyCell, AreaModulusAtTheReferenceSettingFixesC) {
  const fs::path cache = fs::temp_directory_path() / ("dld-study-ka-" + std::to_string(getpid()));
  auto scene_with = [&](double dx, double re, double tau, double ca) {
    const std::string text =
        "[scene]\nname = \"c\"\n[geometry]\npillar_radius_um = 10.0\npillar_spacing_um = "
        "32.0\ndepth_um = 4.8\nrow_shift_um = 4.0\n[lattice]\ndx_um = " +
        std::to_string(dx) + "\ntau = " + std::to_string(tau) +
        "\n[drive]\nreynolds = " + std::to_string(re) +
        "\n[membrane]\nradius_um = 3.9\nmesh_faces = 500\nmodels = [\"skalak\"]\n"
        "capillary_number = " +
        std::to_string(ca) + "\nmesh_cache = \"" + cache.string() +
        "\"\n[membrane.skalak]\narea_modulus_ref_lu = 0.5\n";
    const dld::Scene s = dld::parse_scene(text, "c.toml");
    return dimensionless_cell(s, dld::membrane::read_membrane_scene(s)).area_ratio;
  };
  for (double ca : {0.2, 1.0}) {
    const double c_ref = scene_with(0.4, 0.1, 1.0, ca);
    EXPECT_NEAR(c_ref, 350.28306389557434 * ca, 1e-9 * c_ref);
    EXPECT_NEAR(scene_with(0.8, 0.25, 1.0, ca), c_ref, 1e-10 * c_ref);
    EXPECT_NEAR(scene_with(0.4, 0.25, 0.8, ca), c_ref, 1e-10 * c_ref);
  }
  fs::remove_all(cache);
}

}  // namespace
