// SPDX-License-Identifier: MIT
// Optical-tweezers stretching against Mills et al. 2004 (tests/data/mills2004_with_ranges.txt):
// shared by the coarse default test and the 2000-face long run.
#pragma once
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <vector>

#include "membrane/membrane_scene.hpp"

namespace dld::membrane::test {

struct MillsRow {
  double force_pN, dt, da, dt_lo, dt_hi, da_lo, da_hi;
};

inline std::vector<MillsRow> mills_2004() {
  std::ifstream in(std::string(DLD_TEST_DATA) + "/mills2004_with_ranges.txt");
  std::vector<MillsRow> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    MillsRow r;
    if (s >> r.force_pN >> r.dt >> r.da >> r.dt_lo >> r.dt_hi >> r.da_lo >> r.da_hi)
      rows.push_back(r);
  }
  return rows;
}

/// Runs configs/membrane/<scene> with its mesh face count replaced by `faces`, at the forces of
/// the data, and checks both diameters inside the experimental ranges at every force.
inline void check_against_mills(const std::string& scene_file, int faces) {
  const auto data = mills_2004();
  ASSERT_EQ(data.size(), 13u);
  const Scene scene =
      load_scene(std::string(DLD_SOURCE_DIR) + "/configs/membrane/" + scene_file, false);
  // The face count is the only knob the tests change: rewrite it in the parsed document.
  auto* t = scene.document->root().get_as<toml::table>("membrane");
  ASSERT_NE(t, nullptr);
  const_cast<toml::table*>(t)->insert_or_assign("mesh_faces", faces);
  const_cast<toml::table*>(t)->insert_or_assign("mesh_cache", "cache/meshes");
  const MembraneScene m = read_membrane_scene(scene);
  const LatticeUnits u = scene.units();
  std::vector<double> forces;
  for (const auto& r : data) forces.push_back(u.force_lu(r.force_pN * 1e-12));
  const auto sim = stretch_cell(m.reference_lu, m.mechanics, forces, m.stretch->options);
  std::printf("faces %d (meshed %d)\n  F[pN]   D_A sim [range]          D_T sim [range]\n", faces,
              m.reference_lu.face_count());
  for (std::size_t i = 0; i < data.size(); ++i) {
    const double da = u.length_m(sim[i].axial) * 1e6, dt = u.length_m(sim[i].transverse) * 1e6;
    std::printf("  %6.1f  %6.3f [%6.3f, %6.3f]  %6.3f [%6.3f, %6.3f]  dV/V %+.1e%s\n",
                data[i].force_pN, da, data[i].da_lo, data[i].da_hi, dt, data[i].dt_lo,
                data[i].dt_hi, sim[i].volume_change, sim[i].converged ? "" : " NOT CONVERGED");
    EXPECT_TRUE(sim[i].converged) << data[i].force_pN;
    EXPECT_GE(da, data[i].da_lo) << "D_A at " << data[i].force_pN << " pN";
    EXPECT_LE(da, data[i].da_hi) << "D_A at " << data[i].force_pN << " pN";
    EXPECT_GE(dt, data[i].dt_lo) << "D_T at " << data[i].force_pN << " pN";
    EXPECT_LE(dt, data[i].dt_hi) << "D_T at " << data[i].force_pN << " pN";
  }
}

}  // namespace dld::membrane::test
