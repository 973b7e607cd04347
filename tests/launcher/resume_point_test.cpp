// SPDX-License-Identifier: MIT
// Where dld-run --resume continues (issue 14): the newest step at which the fluid's checkpoint
// and membrane checkpoints holding every cell once meet, whatever split wrote them.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "coupler/launcher/checkpoints.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"
#include "tests/temp_dir.hpp"

namespace dld::coupler {
namespace {

class ResumePointTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  void fluid(const std::string& name, std::int64_t step) const {
    H5File f(path(name), H5File::Mode::kCreate);
    f.write("/fluid/f", std::vector<double>{0.0});
    f.attribute("/fluid", "step", step);
  }
  void cells(const std::string& name, std::int64_t step, int first, int count) const {
    H5File f(path(name), H5File::Mode::kCreate);
    f.write("/membrane/positions", std::vector<double>{0.0});
    f.attribute("/membrane", "step", step);
    f.attribute("/membrane", "first_cell", static_cast<std::int64_t>(first));
    f.attribute("/membrane", "cells", static_cast<std::int64_t>(count));
  }
  std::vector<std::string> parts(int n) const {
    std::vector<std::string> p;
    p.reserve(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) p.push_back(path("cells-" + std::to_string(k)));
    return p;
  }
  /// A run of two processes left step 200 (cells 0-1, 2-3), resumed with three (cells 0, 1-2,
  /// 3) which wrote step 300, the third process only if `third_wrote` (its first checkpoint);
  /// the fluid has 300 and 200 (.prev).
  void two_then_three(bool third_wrote) const {
    fluid("fluid", 300);
    fluid("fluid.prev", 200);
    cells("cells-0", 300, 0, 1);
    cells("cells-1", 300, 1, 2);
    if (third_wrote) cells("cells-2", 300, 3, 1);
    cells("cells-0.prev", 200, 0, 2);
    cells("cells-1.prev", 200, 2, 2);
  }
  test::TempDir dir_{"dld-resume-point"};
};

TEST_F(ResumePointTest, TheNewestStepHoldingEveryCellOnceWins) {
  two_then_three(true);
  const ResumePoint r = coupled_resume_point(path("fluid"), parts(4), 4, 2);
  EXPECT_EQ(r.step, 300);
  EXPECT_EQ(r.fluid, path("fluid"));
  EXPECT_EQ(r.cells, (std::vector<std::string>{path("cells-0"), path("cells-1"), path("cells-2")}));
}

TEST_F(ResumePointTest, AStepWithACellMissingFallsBackToTheOneBefore) {
  two_then_three(false);  // stopped before its third process wrote step 300
  const ResumePoint r = coupled_resume_point(path("fluid"), parts(3), 4, 3);
  EXPECT_EQ(r.step, 200);
  EXPECT_EQ(r.fluid, path("fluid.prev"));
  EXPECT_EQ(r.cells, (std::vector<std::string>{path("cells-0.prev"), path("cells-1.prev")}));
}

TEST_F(ResumePointTest, NoCommonStepNamesEveryFileWithItsStepAndCells) {
  fluid("fluid", 300);
  cells("cells-0", 300, 0, 2);
  cells("cells-1", 200, 2, 2);
  try {
    coupled_resume_point(path("fluid"), parts(3), 4, 3);
    FAIL() << "no step holds cells 2-3 beside the fluid's 300";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path("fluid") + " (step 300)"), std::string::npos) << what;
    EXPECT_NE(what.find(path("cells-1") + " (step 200, cells 2 to 3)"), std::string::npos) << what;
    EXPECT_NE(what.find(path("cells-2") + " (no such file)"), std::string::npos) << what;
  }
}

TEST_F(ResumePointTest, CellsClaimedTwiceAtAStepAreNotATiling) {
  // Step 300 holds cell 1 twice and never cell 3: not a resume point.
  fluid("fluid", 300);
  cells("cells-0", 300, 0, 2);
  cells("cells-1", 300, 1, 2);
  EXPECT_THROW(coupled_resume_point(path("fluid"), parts(2), 4, 2), InputError);
}

}  // namespace
}  // namespace dld::coupler
