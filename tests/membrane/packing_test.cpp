// SPDX-License-Identifier: MIT
// Packed initial states at a coarse setting (dx = 0.8 um, 500-face cells): the study's five states
// are overlap-free and give its haematocrits; the same seed gives the same state, a saved state is
// reused (also through a scene with [cells] count), the clearance and inside checks see images
// across the shifted periodic x face.
#include "membrane/packing.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "membrane/packing_cache.hpp"
#include "packing_states.hpp"
#include "test_meshes.hpp"

namespace dld::membrane {
namespace {

const std::string kScene = std::string(DLD_SOURCE_DIR) + "/configs/membrane/packing_coarse.toml";

class StudyStates : public ::testing::TestWithParam<test::StudyState> {};

TEST_P(StudyStates, AreClearOfTheContactRangeAndGiveTheStudysHaematocrit) {
  test::check_study_state(kScene, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Coarse, StudyStates, ::testing::ValuesIn(test::kStudyStates),
                         [](const auto& param_info) {
                           return std::to_string(param_info.param.cells) + "cells";
                         });

struct Fixture {
  Scene scene = load_scene(kScene, false);
  MembraneScene m = read_membrane_scene(scene);
  DldCell box = scene.cell_lu();
  PackOptions options(int count, std::uint64_t seed) const {
    PackOptions o;
    o.count = count;
    o.seed = seed;
    o.clearance = m.contact->range;
    return o;
  }
};

TEST(Packing, SameSeedSameStateOtherSeedOtherState) {
  const Fixture f;
  const Points a = pack_cells(f.m.reference_lu, f.box, f.options(3, 3)).positions;
  const Points b = pack_cells(f.m.reference_lu, f.box, f.options(3, 3)).positions;
  const Points c = pack_cells(f.m.reference_lu, f.box, f.options(3, 4)).positions;
  EXPECT_EQ((a - b).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT((a - c).cwiseAbs().maxCoeff(), 1.0);
}

TEST(Packing, SavedStateIsReused) {
  const Fixture f;
  const auto dir =
      std::filesystem::temp_directory_path() / ("dld_packing_test_" + std::to_string(getpid()));
  const PackOptions o = f.options(3, 5);
  const CachedPacking first = packed_cells(f.m.reference_lu, f.box, o, dir.string());
  EXPECT_FALSE(first.from_cache);
  ASSERT_TRUE(std::filesystem::exists(first.file)) << first.file;
  const CachedPacking second = packed_cells(f.m.reference_lu, f.box, o, dir.string());
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.file, first.file);
  EXPECT_EQ((first.cells.positions - second.cells.positions).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(second.cells.report.iterations, first.cells.report.iterations);
  // Another seed or geometry is another file.
  EXPECT_NE(packing_file_name(f.m.reference_lu, f.box, f.options(3, 6)),
            packing_file_name(f.m.reference_lu, f.box, o));
  DldCell shifted = f.box;
  shifted.shift += 1.0;
  EXPECT_NE(packing_file_name(f.m.reference_lu, shifted, o),
            packing_file_name(f.m.reference_lu, f.box, o));
  // A file whose key does not match is refused, naming the file.
  try {
    read_packing(first.file, "0000000000000000", 3, f.m.reference_lu.node_count());
    ADD_FAILURE() << "a wrong key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(first.file), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(Packing, SceneWithCountBuildsThePackedCellsAndReusesThem) {
  std::ifstream in(kScene);
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("dld_packing_scene_test_" + std::to_string(getpid()));
  t.replace(t.find("count = 17"), 10, "count = 3\npacking_cache = \"" + dir.string() + "\"");
  const Scene scene = parse_scene(t, "packing.toml", false);
  const MembraneScene m = read_membrane_scene(scene);
  const CellSet a = build_cells(m, scene);  // packs and saves
  ASSERT_EQ(a.cell_count(), 3);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
  const CellSet b = build_cells(m, scene);  // loads
  EXPECT_EQ((a.positions() - b.positions()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(100.0 * haematocrit(a, scene.cell_lu()), 8.0, 1.0);
  std::filesystem::remove_all(dir);
}

TEST(Clearance, SeesImagesAcrossTheShiftedXFace) {
  // Two one-node "cells": one just inside x = lambda, one just inside x = 0 at y - d, which is the
  // same point shifted; 0.3 apart through the face, far apart inside the box.
  const DldCell box{80.0, 25.0, 12.0, 11.0};
  Points x(3, 2);
  x.col(0) << 79.9, 20.0, 6.0;
  x.col(1) << 0.2, 20.0 - 11.0, 6.0;
  EXPECT_NEAR(clearances(x, 1, box, 10.0).cells, 0.3, 1e-9);
  x.col(1) << 0.2, 20.0, 6.0;  // without the shift it is 11 away through the face
  EXPECT_NEAR(clearances(x, 1, box, 20.0).cells, std::hypot(0.3, 11.0), 1e-9);
  EXPECT_NEAR(clearances(x, 1, box, 20.0).walls, 6.0, 1e-12);
}

TEST(Clearance, FindsNodesInsideAnotherCell) {
  // Two octahedra (radius 1): apart, none inside; overlapping by half, the tip of each is inside
  // the other, also when the overlap goes through the shifted x face.
  const TriMesh o = test::octahedron();
  const DldCell box{80.0, 25.0, 12.0, 11.0};
  Points x(3, 12);
  x.leftCols(6) = o.nodes.colwise() + Eigen::Vector3d(10.0, 10.0, 6.0);
  x.rightCols(6) = o.nodes.colwise() + Eigen::Vector3d(13.0, 10.0, 6.0);
  EXPECT_EQ(nodes_inside_other_cells(x, o.faces, 6, box), 0);
  x.rightCols(6) = o.nodes.colwise() + Eigen::Vector3d(11.5, 10.0, 6.0);
  EXPECT_EQ(nodes_inside_other_cells(x, o.faces, 6, box), 2);
  x.leftCols(6) = o.nodes.colwise() + Eigen::Vector3d(79.5, 30.0, 6.0);
  x.rightCols(6) = o.nodes.colwise() + Eigen::Vector3d(1.0 - 0.5, 30.0 - 11.0, 6.0);
  EXPECT_EQ(nodes_inside_other_cells(x, o.faces, 6, box), 2);
}

}  // namespace
}  // namespace dld::membrane
