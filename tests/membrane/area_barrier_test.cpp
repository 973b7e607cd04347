// SPDX-License-Identifier: MIT
// The area barrier (membrane/area_barrier.hpp): nothing at all while every triangle stays above
// its onset; below it, a compressed triangle keeps being pushed back where Skalak's area term
// gives way; its scene keys.
#include <gtest/gtest.h>

#include <string>
#include <variant>

#include "membrane/membrane_scene.hpp"
#include "membrane/model_registry.hpp"
#include "test_meshes.hpp"
#include "tests/common/base_scene.hpp"

namespace dld::membrane {
namespace {

template <typename Model>
Points forces_of(const Model& m, const Points& x) {
  Points f = Points::Zero(3, x.cols());
  m.add_forces(x, f);
  return f;
}

// One flat triangle, equilateral at rest (edge 1), its apex (node 2) pushed towards the base so
// that A/A_rest = j; returns the apex's force along +y (away from the base: the push back).
template <typename Model>
double push_back(const Model& m, double j) {
  Points x(3, 3);
  const double h = std::sqrt(3.0) / 2;
  x << 0, 1, 0.5, 0, 0, h * j, 0, 0, 0;
  return forces_of(m, x)(1, 2);
}

TriMesh flat_triangle() {
  TriMesh t;
  t.nodes.resize(3, 3);
  t.nodes << 0, 1, 0.5, 0, 0, std::sqrt(3.0) / 2, 0, 0, 0;
  t.faces = {{0, 1, 2}};
  return t;
}

TEST(AreaBarrier, ACompressedTriangleKeepsBeingPushedBackWhereSkalakGivesWay) {
  const TriMesh t = flat_triangle();
  const double ka = 100.0;  // C = 100, as stiff as the study's cells (C 70-350)
  const SkalakModel skalak(t, {1.0, ka});
  const AreaBarrier barrier(t, {ka, 0.6});
  auto total = [&](double j) { return push_back(skalak, j) + push_back(barrier, j); };
  // Skalak alone: the push back peaks near J = 1/sqrt(3) and fades as J -> 0 ...
  EXPECT_GT(push_back(skalak, 0.55), 1.9 * push_back(skalak, 0.2));
  EXPECT_GT(push_back(skalak, 0.2), 3.5 * push_back(skalak, 0.05));
  // ... with the barrier it grows all the way down.
  double previous = total(0.6);
  for (double j : {0.5, 0.4, 0.3, 0.2, 0.1, 0.05, 0.01}) {
    SCOPED_TRACE(j);
    EXPECT_GT(total(j), previous);
    previous = total(j);
  }
  EXPECT_GT(total(0.01), 4 * push_back(skalak, 0.55));
  // The barrier's push is kappa_b (J_b - J) A_rest dJ/dy = kappa_b (J_b - J) / 2 here, down to
  // J = 1e-5; and bounded by its value at J = 0 where the triangle flattens completely.
  for (double j : {0.59, 0.3, 1e-3, 1e-5})
    EXPECT_NEAR(push_back(barrier, j), ka * (0.6 - j) / 2, 1e-5 * ka);
  for (double j : {1e-7, 1e-9, 0.0}) {
    EXPECT_TRUE(std::isfinite(push_back(barrier, j)));
    EXPECT_LE(std::abs(push_back(barrier, j)), ka * 0.6 / 2 * (1 + 1e-9));
  }
}

TEST(AreaBarrier, TrianglesAboveTheOnsetFeelNothingAndTheCellMovesAsWithoutIt) {
  const TriMesh ref = test::cell_mesh(300, 4.0);
  const AreaBarrier barrier(ref, {1.0, 0.6});
  Points x = ref.nodes;
  x.row(0) *= 0.8;
  x = test::perturbed(x, 0.05, 3);
  EXPECT_EQ(barrier.energy(x), 0.0);
  EXPECT_EQ(forces_of(barrier, x).cwiseAbs().maxCoeff(), 0.0);
  // Skalak with and without the barrier: the same forces bit for bit.
  const MembraneMechanics alone({"skalak"}, {SkalakModel(ref, {1.0, 50.0})});
  const MembraneMechanics both({"skalak", "area_barrier"},
                               {SkalakModel(ref, {1.0, 50.0}), barrier});
  Points fa = Points::Zero(3, x.cols()), fb = fa;
  alone.add_forces(x, fa);
  both.add_forces(x, fb);
  EXPECT_EQ((fa - fb).cwiseAbs().maxCoeff(), 0.0);
  // Squeezed to 40 % along one axis, triangles pass the onset and it acts.
  x.row(0) *= 0.5;
  EXPECT_GT(barrier.energy(x), 0.0);
}

TEST(AreaBarrier, BadParametersAreRefused) {
  const TriMesh m = test::octahedron();
  EXPECT_THROW(AreaBarrier(m, {-1.0, 0.6}), InputError);
  EXPECT_THROW(AreaBarrier(m, {1.0, 0.0}), InputError);
  EXPECT_THROW(AreaBarrier(m, {1.0, 1.5}), InputError);
  EXPECT_THROW(AreaBarrier(m, {std::nan(""), 0.6}), InputError);
}

// The base scene with a Skalak cell and the barrier at `barrier` (its table's lines).
MembraneScene scene_with(const std::string& barrier, double ca) {
  const std::string membrane = R"(
[membrane]
mesh_faces = 300
mesh_cache = "cache/meshes"
models = ["skalak", "bending", "volume", "area_barrier"]
capillary_number = )" + std::to_string(ca) +
                               R"(
[membrane.skalak]
area_modulus_ref_lu = 0.5
[membrane.bending]
modulus_rel = 2.5e-3
[membrane.volume]
modulus_rel = 100.0
[membrane.area_barrier]
)" + barrier;
  const Scene s = parse_scene(std::string(dld::testing::kBaseScene) + membrane, "t.toml", false);
  return read_membrane_scene(s);
}

template <typename Model>
const Model& model_of(const MembraneScene& m) {
  for (const auto& model : m.mechanics.models())
    if (const auto* p = std::get_if<Model>(&model)) return *p;
  throw std::logic_error("model missing");
}

TEST(AreaBarrier, ItsModulusKeepsItsRatioToSkalaksAreaModulusAtEveryCa) {
  for (double ca : {0.2, 1.0}) {
    const MembraneScene m = scene_with("modulus_ref_lu = 0.5\nbelow = 0.6\n", ca);
    const auto& skalak = model_of<SkalakModel>(m);
    const auto& barrier = model_of<AreaBarrier>(m);
    EXPECT_NEAR(barrier.law().p.modulus / skalak.law().p.kappa_alpha, 1.0, 1e-12);
    EXPECT_EQ(barrier.law().p.below, 0.6);
  }
}

TEST(AreaBarrier, BadSceneKeysAreNamed) {
  auto error = [](const std::string& table) {
    try {
      scene_with(table, 0.2);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = error("modulus_ref_lu = 0.5\nbelow = 1.5\n");
  EXPECT_NE(e.find("membrane.area_barrier.below"), std::string::npos) << e;
  e = error("below = 0.6\n");
  EXPECT_NE(e.find("membrane.area_barrier.modulus_ref_lu"), std::string::npos) << e;
  e = error("modulus_ref_lu = -1\nbelow = 0.6\n");
  EXPECT_NE(e.find("membrane.area_barrier.modulus_ref_lu"), std::string::npos) << e;
}

}  // namespace
}  // namespace dld::membrane
