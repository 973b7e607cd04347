// SPDX-License-Identifier: MIT
// Bad input is refused with a one-line InputError naming what is wrong: meshes (open,
// non-manifold, inverted, degenerate, malformed files), model parameters, scene keys.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

#include "membrane/membrane_scene.hpp"
#include "test_meshes.hpp"
#include "tests/common/base_scene.hpp"

namespace dld::membrane {
namespace {

std::string refusal(const TriMesh& m) {
  try {
    validate_closed_surface(m, "bad.off");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BadMesh, GoodOctahedronPasses) {
  EXPECT_EQ(refusal(test::octahedron()), "");
}

TEST(BadMesh, OpenSurfaceIsRefused) {
  TriMesh m = test::octahedron();
  m.faces.pop_back();
  EXPECT_NE(refusal(m).find("open"), std::string::npos) << refusal(m);
}

TEST(BadMesh, InvertedSurfaceIsRefused) {
  TriMesh m = test::octahedron();
  for (Face& t : m.faces) std::swap(t[1], t[2]);
  EXPECT_NE(refusal(m).find("inverted"), std::string::npos) << refusal(m);
}

TEST(BadMesh, InconsistentOrientationIsRefused) {
  TriMesh m = test::octahedron();
  std::swap(m.faces[0][1], m.faces[0][2]);
  EXPECT_NE(refusal(m).find("oriented"), std::string::npos) << refusal(m);
}

TEST(BadMesh, NonManifoldVertexIsRefused) {
  // Two octahedra touching at one node (the copy's node 1 is node 0 of the first): every edge has
  // two faces, but the shared node has two separate fans.
  const TriMesh a = test::octahedron();
  TriMesh m = a;
  m.nodes.conservativeResize(3, 11);
  std::array<int, 6> map{6, 0, 7, 8, 9, 10};
  for (int i = 0; i < 6; ++i)
    if (i != 1) m.nodes.col(map[i]) = a.nodes.col(i) + Eigen::Vector3d(2, 0, 0);
  for (const Face& t : a.faces) m.faces.push_back({map[t[0]], map[t[1]], map[t[2]]});
  EXPECT_NE(refusal(m).find("non-manifold vertex"), std::string::npos) << refusal(m);
}

TEST(BadMesh, NonManifoldEdgeIsRefused) {
  TriMesh m = test::octahedron();
  m.faces.push_back(m.faces[0]);
  EXPECT_NE(refusal(m).find("non-manifold"), std::string::npos) << refusal(m);
}

TEST(BadMesh, DegenerateTriangleIsRefused) {
  TriMesh m = test::octahedron();
  m.nodes.col(4) = 0.5 * (m.nodes.col(0) + m.nodes.col(2));  // apex onto an edge: face 0 flat
  EXPECT_NE(refusal(m).find("degenerate"), std::string::npos) << refusal(m);
  TriMesh r = test::octahedron();
  r.faces[0] = {0, 0, 4};
  EXPECT_NE(refusal(r).find("degenerate"), std::string::npos) << refusal(r);
}

TEST(BadMesh, MalformedOffFileIsRefused) {
  const std::string path = "bad_mesh_test.off";
  std::ofstream(path) << "OFF\n4 1 0\n0 0 0\n1 0 0\n";
  EXPECT_THROW(read_off(path), InputError);
  std::ofstream(path) << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2 0\n";
  EXPECT_THROW(read_off(path), InputError);
  EXPECT_THROW(read_off("no_such_file.off"), InputError);
  std::filesystem::remove(path);
}

TEST(BadParameters, ModelsRefuseThem) {
  const TriMesh m = test::octahedron();
  EXPECT_THROW(SkalakModel(m, {-1.0, 1.0}), InputError);
  EXPECT_THROW(SkalakModel(m, {1.0, -1.0}), InputError);
  EXPECT_THROW(SkalakModel(m, {std::nan(""), 1.0}), InputError);
  EXPECT_THROW(NeoHookeanModel(m, {0.0}), InputError);
  EXPECT_THROW(BendingModel(m, {-1.0}), InputError);
  EXPECT_THROW(VolumePenalty(m, {-1.0}), InputError);
  EXPECT_THROW(AreaPenalty(m, {-1.0}), InputError);
}

// The base scene driven by p' = 1e5 Pa/m, the value the kappa_s test's formula uses.
const std::string kBase = [] {
  std::string s = dld::testing::kBaseScene;
  const std::string re = "reynolds = 0.1";
  return s.replace(s.find(re), re.size(), "pressure_gradient_Pa_per_m = 1.0e5");
}();

std::string scene_error(const std::string& membrane) {
  try {
    const Scene s = parse_scene(std::string(kBase) + membrane, "t.toml", false);
    read_membrane_scene(s);
    s.document->reject_unknown({"coupling"});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

const std::string kGood = R"(
[membrane]
mesh_faces = 300
mesh_cache = "cache/meshes"
models = ["skalak", "bending", "volume"]
capillary_number = 0.2
[membrane.skalak]
area_ratio = 10.0
[membrane.bending]
modulus_rel = 2.5e-3
[membrane.volume]
modulus_rel = 100.0
)";

TEST(SceneKeys, GoodSceneIsAccepted) {
  EXPECT_EQ(scene_error(kGood), "");
}

TEST(SceneKeys, CapillaryNumberGivesKappaS) {
  const Scene s = parse_scene(std::string(kBase) + kGood, "t.toml", false);
  const MembraneScene m = read_membrane_scene(s);
  // kappa_s = p' sqrt(G H) r / Ca = 1e5 * sqrt(12e-6 * 4.8e-6) * 3.9e-6 / 0.2
  EXPECT_NEAR(m.kappa_s_N_per_m, 1e5 * std::sqrt(12e-6 * 4.8e-6) * 3.9e-6 / 0.2, 1e-15);
  EXPECT_NEAR(m.kappa_s_lu, s.units().modulus_lu(m.kappa_s_N_per_m), 1e-18);
}

TEST(SceneKeys, ErrorsNameFileLineAndKey) {
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = kGood;
    t.replace(t.find(from), from.size(), to);
    return scene_error(t);
  };
  std::string e = with("\"skalak\", \"bending\"", "\"skalek\", \"bending\"");
  EXPECT_NE(e.find("unknown membrane model 'skalek'"), std::string::npos) << e;
  EXPECT_NE(e.find("t.toml:"), std::string::npos) << e;
  e = with("capillary_number = 0.2", "capillary_number = 0.2\nkappa_s_N_per_m = 1e-5");
  EXPECT_NE(e.find("exactly one"), std::string::npos) << e;
  e = with("area_ratio = 10.0", "area_ratio = -1.0");
  EXPECT_NE(e.find("membrane.skalak.area_ratio"), std::string::npos) << e;
  e = with("modulus_rel = 100.0", "modulus_rel = 100.0\nmodulus = 3");
  EXPECT_NE(e.find("membrane.volume.modulus"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown key"), std::string::npos) << e;
  e = with("mesh_faces = 300", "mesh_faces = 20");
  EXPECT_NE(e.find("membrane.mesh_faces"), std::string::npos) << e;
  e = with("[membrane.bending]\nmodulus_rel = 2.5e-3\n", "");
  EXPECT_NE(e.find("[membrane.bending]"), std::string::npos) << e;
  e = scene_error(kGood + "[[cells.cell]]\ncentre_um = [16.0, 16.0, 2.4]\n");
  EXPECT_NE(e.find("inside the pillar"), std::string::npos) << e;
  // NaN compares false with every limit: it must be refused by name, not slip through them.
  e = scene_error(kGood + "[[cells.cell]]\ncentre_um = [3.0, nan, 2.4]\n");
  EXPECT_NE(e.find("cells.cell"), std::string::npos) << e;
  EXPECT_NE(e.find("centre_um"), std::string::npos) << e;
  EXPECT_NE(e.find("expected finite numbers"), std::string::npos) << e;
  e = scene_error(kGood + "[[cells.cell]]\ncentre_um = [3.0, 0.0, 2.4]\nangle_deg = inf\n");
  EXPECT_NE(e.find("angle_deg"), std::string::npos) << e;
}

// kappa_V of the scene's volume penalty (lattice units).
double volume_modulus(const std::string& membrane) {
  const Scene s = parse_scene(std::string(kBase) + membrane, "t.toml", false);
  const MembraneScene m = read_membrane_scene(s);
  for (const auto& model : m.mechanics.models()) {
    if (const auto* v = std::get_if<VolumePenalty>(&model)) return v->params().kappa_v;
  }
  return -1.0;
}

TEST(SceneKeys, VolumeModulusFollowsKappaSUnlessAReferenceCaIsGiven) {
  auto at = [](double ca, const std::string& extra) {
    std::string t = kGood;
    t.replace(t.find("capillary_number = 0.2"), 22, "capillary_number = " + std::to_string(ca));
    return volume_modulus(t + extra);
  };
  // modulus_rel alone: kappa_V = 100 kappa_s / r, so 5 times weaker at Ca 1.0 than at 0.2.
  EXPECT_NEAR(at(0.2, "") / at(1.0, ""), 5.0, 1e-12);
  // With the reference Ca, kappa_V is that of Ca 0.2 at every Ca.
  const std::string ref = "reference_capillary_number = 0.2\n";
  EXPECT_NEAR(at(1.0, ref) / at(0.2, ""), 1.0, 1e-12);
  EXPECT_NEAR(at(0.5, ref) / at(0.2, ""), 1.0, 1e-12);
  // Without a Ca (kappa_s given directly) there is nothing to refer to.
  std::string direct = kGood;
  direct.replace(direct.find("capillary_number = 0.2"), 22, "kappa_s_N_per_m = 1e-5");
  const std::string e = scene_error(direct + ref);
  EXPECT_NE(e.find("membrane.volume.reference_capillary_number"), std::string::npos) << e;
  EXPECT_NE(e.find("needs [membrane] capillary_number"), std::string::npos) << e;
  EXPECT_NE(scene_error(kGood + "reference_capillary_number = -1\n").find("positive"),
            std::string::npos);
}

TEST(SceneKeys, UserMeshFileIsChecked) {
  std::string base = kGood;
  base.replace(base.find("mesh_faces = 300\n"), 17, "mesh_file = \"user_mesh_test.off\"\n");
  TriMesh m = test::octahedron();
  write_off(m, "user_mesh_test.off");
  EXPECT_EQ(scene_error(base), "");
  for (Face& t : m.faces) std::swap(t[1], t[2]);
  write_off(m, "user_mesh_test.off");
  const std::string e = scene_error(base);
  EXPECT_NE(e.find("user_mesh_test.off: the enclosed volume is not positive"), std::string::npos)
      << e;
  m.faces.pop_back();
  write_off(m, "user_mesh_test.off");
  EXPECT_NE(scene_error(base).find("open"), std::string::npos) << scene_error(base);
  std::filesystem::remove("user_mesh_test.off");
  EXPECT_NE(scene_error(base).find("cannot open mesh file"), std::string::npos)
      << scene_error(base);
  std::string both = kGood;
  both.replace(both.find("mesh_faces = 300\n"), 17, "mesh_faces = 300\nmesh_file = \"x.off\"\n");
  EXPECT_NE(scene_error(both).find("not both"), std::string::npos) << scene_error(both);
}

TEST(SceneKeys, PackedCellsKeysAreChecked) {
  const std::string cell = "[[cells.cell]]\ncentre_um = [3.0, 3.0, 2.4]\n";
  EXPECT_EQ(scene_error(kGood + "[cells]\ncount = 3\nseed = 7\n"), "");
  std::string e = scene_error(kGood + "[cells]\ncount = 0\n");
  EXPECT_NE(e.find("t.toml:"), std::string::npos) << e;
  EXPECT_NE(e.find("cells.count"), std::string::npos) << e;
  EXPECT_NE(e.find("expected 1..200"), std::string::npos) << e;
  e = scene_error(kGood + "[cells]\ncount = 3\nseed = -1\n");
  EXPECT_NE(e.find("cells.seed"), std::string::npos) << e;
  e = scene_error(kGood + "[cells]\nseed = 2\n");
  EXPECT_NE(e.find("only used with count"), std::string::npos) << e;
  e = scene_error(kGood + "[cells]\ncount = 3\n" + cell);
  EXPECT_NE(e.find("not both"), std::string::npos) << e;
  e = scene_error(kGood + "[cells]\ncount = \"many\"\n");
  EXPECT_NE(e.find("cells.count"), std::string::npos) << e;
}

TEST(SceneKeys, ExpectedModeIsOptionalAndChecked) {
  const auto mode = [](const std::string& cells) {
    return read_membrane_scene(parse_scene(std::string(kBase) + kGood + cells, "t.toml", false))
        .expected_mode;
  };
  const std::string cell = "[[cells.cell]]\ncentre_um = [3.0, 3.0, 2.4]\n";
  EXPECT_FALSE(mode(cell).has_value());
  EXPECT_EQ(mode("[cells]\nexpected_mode = \"zigzag\"\n" + cell), TransportMode::kZigzag);
  EXPECT_EQ(mode("[cells]\ncount = 3\nexpected_mode = \"displacement\"\n"),
            TransportMode::kDisplacement);
  // A bad value stops with one line naming file, line and key (line 26: kBase and kGood are 24
  // lines, then [cells]).
  const std::string e = scene_error(kGood + "[cells]\nexpected_mode = \"mixed\"\n" + cell);
  EXPECT_NE(e.find("t.toml:26:"), std::string::npos) << e;
  EXPECT_NE(e.find("cells.expected_mode"), std::string::npos) << e;
  EXPECT_NE(e.find("mixed"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

}  // namespace
}  // namespace dld::membrane
