// SPDX-License-Identifier: MIT
// The pace of a run's cells (analysis/pace): synthetic tracks with known columns per step.
#include "analysis/pace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "synthetic.hpp"

namespace dld::analysis {
namespace {

using testing::kLambda;
using testing::track;

analysis::Run run_of(std::vector<CellTrack> cells) {
  analysis::Run r;
  r.scene_name = "synthetic";
  r.lambda_um = kLambda;
  r.row_shift_um = 4.4;
  r.files = {"synthetic-cells-0.h5"};
  r.cells = std::move(cells);
  return r;
}

const auto flat = [](double) { return 0.0; };

// track() spreads `columns` over 2000 samples 100 steps apart: 200 000 steps in all.
TEST(Pace, EachCellsPillarsAndStepsPerPillarFromItsOwnPath) {
  const RunPace p = run_pace(run_of(
      {track(0, 3.0, 1.0, 2.0, flat), track(1, 5.0, 8.0, 0.5, flat), track(2, 7.0, 9.0, 1.0, flat),
       track(3, 2.0, 3.0, 4.0, [](double c) { return testing::wiggle(c); })}));
  ASSERT_EQ(p.cells.size(), 4u);
  EXPECT_DOUBLE_EQ(p.first_step, 0);
  EXPECT_DOUBLE_EQ(p.last_step, 200000);
  EXPECT_NEAR(p.cells[0].pillars, 2.0, 1e-12);
  EXPECT_NEAR(p.cells[0].steps_per_pillar, 100000, 1e-6);
  EXPECT_NEAR(p.cells[1].steps_per_pillar, 400000, 1e-6);
  EXPECT_NEAR(p.cells[3].pillars, 4.0, 1e-12);  // y wiggles do not count
  EXPECT_NEAR(p.mean_pillars, 7.5 / 4, 1e-12);
  EXPECT_NEAR(p.median_pillars, 1.5, 1e-12);
  EXPECT_NEAR(p.mean_steps_per_pillar(), 200000 / (7.5 / 4), 1e-6);
  // 20 pillars: the cell at 0.5 columns per 200 000 steps arrives last, at step 8 000 000.
  int slowest = -1;
  EXPECT_NEAR(p.step_every_cell_at(20, &slowest), 8e6, 1e-3);
  EXPECT_EQ(slowest, 1);
  // 1 pillar: cells 0, 2 and 3 are there already; cell 1 needs 400 000 steps in all.
  EXPECT_NEAR(p.step_every_cell_at(1, &slowest), 4e5, 1e-6);
  EXPECT_EQ(slowest, 1);
}

TEST(Pace, ACellThatHasNotAdvancedNeverArrives) {
  const RunPace p =
      run_pace(run_of({track(0, 3.0, 1.0, 2.0, flat), track(1, 9.0, 8.0, 0.0, flat)}));
  EXPECT_TRUE(std::isinf(p.cells[1].steps_per_pillar));
  int slowest = -1;
  EXPECT_TRUE(std::isinf(p.step_every_cell_at(20, &slowest)));
  EXPECT_EQ(slowest, 1);
  // Every cell that must arrive has advanced: a finite step.
  const RunPace q = run_pace(run_of({track(0, 3.0, 1.0, 2.0, flat)}));
  EXPECT_NEAR(q.step_every_cell_at(2), 200000, 1e-6);
}

// A cell that advances 3 columns in the first 100 000 steps and then stays at a pillar (x within
// a few um) for the other 300 000 is held, and said so; the cells that keep moving are not.
TEST(Pace, ACellStoppedForLongIsReportedHeldSinceItStopped) {
  CellTrack held = track(2, 10.0, 5.0, 3.0, flat, 1000);  // 3 columns in 100 000 steps
  for (int s = 1; s <= 3000; ++s) {
    held.step.push_back(100000.0 + 100.0 * s);
    held.position.push_back({10.0 + 3 * kLambda + 2.0 * std::sin(s * 0.01), 5.0 - 0.002 * s, 2.4});
    held.volume.push_back(94.0);
  }
  CellTrack a = track(0, 3.0, 1.0, 16.0, flat, 4000), b = track(1, 5.0, 8.0, 12.0, flat, 4000);
  const analysis::Run r = run_of({a, b, held});
  const RunPace p = run_pace(r);
  ASSERT_EQ(p.held_cells().size(), 1u);
  EXPECT_EQ(p.held_cells()[0].id, 2);
  // Its last x is 106 + 2 sin 30 = 104.02 um; the approach enters the band x > 96.02 at sample
  // 897 (x = 10 + 96 s / 1000): held since step 89 700.
  EXPECT_DOUBLE_EQ(p.held_cells()[0].still_since, 89700);
  const std::string table = format_pace(r, p, 20);
  EXPECT_NE(table.find("held: cell 2 has stayed within lambda/4 in x since step 89 700 "),
            std::string::npos)
      << table;
  EXPECT_EQ(table.find("held: cell 0"), std::string::npos) << table;
  // The same cell held for less than twice the mean cell's steps per pillar is only slow.
  held.step.resize(1000 + 200);
  held.position.resize(1000 + 200);
  held.volume.resize(1000 + 200);
  a = track(0, 3.0, 1.0, 1.2, flat, 1200), b = track(1, 5.0, 8.0, 1.2, flat, 1200);
  EXPECT_TRUE(run_pace(run_of({a, b, held})).held_cells().empty());
}

TEST(Pace, OneSampleIsAnErrorNamingTheFileAndCell) {
  CellTrack t = track(5, 3.0, 1.0, 2.0, flat);
  t.step.resize(1);
  t.position.resize(1);
  t.volume.resize(1);
  const std::string e = testing::error_of([&] { run_pace(run_of({t})); });
  EXPECT_NE(e.find("synthetic-cells-0.h5: cell 5 has 1 samples"), std::string::npos) << e;
}

TEST(Pace, TheTableNamesTheLastCellAndTheCsvHasOneRowPerCell) {
  const analysis::Run r = run_of({track(0, 3.0, 1.0, 2.0, flat), track(1, 5.0, 8.0, 0.5, flat)});
  const RunPace p = run_pace(r);
  const std::string table = format_pace(r, p, 20);
  EXPECT_NE(table.find("step 8 000 000 (cell 1 last)"), std::string::npos) << table;
  const std::string dir = testing::temp_dir("pace");
  const std::string csv = write_pace_csv(p, 20, dir, "run");
  std::ifstream in(csv);
  std::string header, row0, row1, more;
  std::getline(in, header);
  std::getline(in, row0);
  std::getline(in, row1);
  EXPECT_EQ(header, "cell,pillars,steps_per_pillar,step_at_20_pillars,still_since_step");
  // Moving cells: x entered the band lambda/4 = 8 um below its last value at x = 59 (cell 0,
  // sample 1751) and x = 13 (cell 1, sample 1001).
  EXPECT_EQ(row0, "0,2.0000,100000,2000000,175100");
  EXPECT_EQ(row1, "1,0.5000,400000,8000000,100100");
  EXPECT_FALSE(std::getline(in, more));
}

}  // namespace
}  // namespace dld::analysis
