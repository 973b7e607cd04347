// SPDX-License-Identifier: MIT
// Membrane checkpoints of any split (issue 14): a process takes its cells from the checkpoints
// another number of processes wrote, and refuses a set that does not hold them once at one step.
#include "membrane/run_checkpoint.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "shared/input_error.hpp"
#include "tests/temp_dir.hpp"

namespace dld::membrane {
namespace {

constexpr int kNodes = 3;  // nodes per cell

/// Cells [first, first + cells) at `step`: node j of cell c at (c, j, step); two sample rows.
RunCheckpoint part(int first, int cells, std::int64_t step = 100) {
  RunCheckpoint c{step, "abc", first, cells, kNodes, Points(3, cells * kNodes), {}};
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < kNodes; ++j)
      c.positions.col(k * kNodes + j) << first + k, j, static_cast<double>(step);
  for (const double s : {50.0, 100.0}) {
    c.rows.push_back(s);
    for (int k = 0; k < cells; ++k)
      for (int v = 0; v < 4; ++v) c.rows.push_back(s + 10 * (first + k) + v);
  }
  return c;
}

RunCheckpoint wanted(int first, int cells) {
  return RunCheckpoint{0, "abc", first, cells, kNodes, {}, {}};
}

class RunCheckpoints : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const RunCheckpoint& c) {
    std::string path = (dir_.path() / name).string();
    write_run_checkpoint(path, c);
    return path;
  }
  test::TempDir dir_{"dld-run-ckpt"};
};

TEST_F(RunCheckpoints, AProcessTakesItsCellsFromAnotherSplit) {
  // Written by two processes (cells 0-1, 2-3), read by the middle one of three (cells 1-2).
  const std::vector<std::string> files{write("a", part(2, 2)), write("b", part(0, 2))};
  const RunCheckpoint c = read_run_checkpoints(files, wanted(1, 2));
  EXPECT_EQ(c.step, 100);
  ASSERT_EQ(c.positions.cols(), 2 * kNodes);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < kNodes; ++j) {
      EXPECT_EQ(c.positions(0, k * kNodes + j), 1 + k);
      EXPECT_EQ(c.positions(1, k * kNodes + j), j);
    }
  // Each row: the step, then this process's cells' four values, as the one-process run has them.
  const RunCheckpoint one = part(1, 2);
  EXPECT_EQ(c.rows, one.rows);
}

TEST_F(RunCheckpoints, ASetWithoutOneOfTheCellsIsRefusedNamingIt) {
  const std::vector<std::string> files{write("a", part(0, 2)), write("b", part(3, 1))};
  try {
    read_run_checkpoints(files, wanted(1, 3));
    FAIL() << "no checkpoint holds cell 2";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no checkpoint holds cell 2"), std::string::npos)
        << e.what();
  }
}

TEST_F(RunCheckpoints, ACellClaimedTwiceIsRefusedNamingBothFiles) {
  const std::string a = write("a", part(0, 2)), b = write("b", part(1, 2));
  try {
    read_run_checkpoints({a, b}, wanted(0, 3));
    FAIL() << "cell 1 is in both files";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(b + ": /membrane first_cell 1"), std::string::npos) << what;
    EXPECT_NE(what.find("claimed by " + a), std::string::npos) << what;
  }
}

TEST_F(RunCheckpoints, CheckpointsOfDifferentStepsAreRefused) {
  const std::string a = write("a", part(0, 2, 100)), b = write("b", part(2, 2, 200));
  EXPECT_THROW(read_run_checkpoints({a, b}, wanted(0, 4)), InputError);
}

TEST_F(RunCheckpoints, AnotherScenesOrMeshsCheckpointIsRefused) {
  const std::string a = write("a", part(0, 2));
  RunCheckpoint other_scene = wanted(0, 2);
  other_scene.scene_hash = "abd";
  EXPECT_THROW(read_run_checkpoints({a}, other_scene), InputError);
  RunCheckpoint other_mesh = wanted(0, 2);
  other_mesh.nodes_per_cell = kNodes + 1;
  EXPECT_THROW(read_run_checkpoints({a}, other_mesh), InputError);
  EXPECT_THROW(read_run_checkpoints({a + ".missing"}, wanted(0, 2)), InputError);
}

}  // namespace
}  // namespace dld::membrane
