// SPDX-License-Identifier: MIT
// Failure probabilities and outlets (SPEC section 7) on synthetic paths with known answers.
#include "analysis/evaluation.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "analysis/outlets.hpp"
#include "analysis/run_analysis.hpp"
#include "synthetic.hpp"

namespace dld::analysis {
namespace {

using testing::kLambda;
using testing::steps;
using testing::track;
using testing::wiggle;

constexpr double kD = 4.4;
const ExpectedMode kZigzag{TransportMode::kZigzag, "test"};
const ExpectedMode kDisplacement{TransportMode::kDisplacement, "test"};
// The wiggle is sampled 20 times per column and interpolated linearly: y(N) is off by at most
// h^2/8 max|y''| ~ 0.01 um near a whole column, so p_f by at most 4e-6.
constexpr double kInterpolation = 1e-5;

Run run_of(std::vector<CellTrack> cells, double d = kD) {
  Run r;
  r.stem = "synthetic";
  r.files = {"synthetic-cells-0.h5"};
  r.lambda_um = kLambda;
  r.row_shift_um = d;
  r.cells = std::move(cells);
  return r;
}

TEST(Evaluation, YAtAdvanceInterpolatesBetweenSamples) {
  CellTrack t;
  t.position = {{1, 2, 0}, {11, 4, 0}, {31, 14, 0}};
  EXPECT_NEAR(*y_at_advance(t, 20.0), 9.0, 1e-12);  // x = 21: half-way from x = 11 to 31
  EXPECT_FALSE(y_at_advance(t, 31.0).has_value());
}

TEST(Evaluation, IdealZigzagFailsNeverAndEndsInO1OrO2) {
  std::vector<CellTrack> cells;
  cells.reserve(4);
  for (int k = 0; k < 4; ++k) {
    cells.push_back(track(k, 3.0 + k, 2.0 + 7.0 * k, 100.5, [](double c) { return wiggle(c); }));
  }
  const RunAnalysis a = analyze_run(run_of(cells), 100, kZigzag);
  EXPECT_NEAR(a.p_f.mean, 0.0, kInterpolation);
  EXPECT_NEAR(a.p_f.std, 0.0, kInterpolation);
  EXPECT_EQ(a.p_f.n, 4);
  for (const auto& c : a.cells) {
    EXPECT_EQ(c.mode, TransportMode::kZigzag);
  }
  EXPECT_EQ(a.outlets.count[1] + a.outlets.count[2], 4);
  EXPECT_DOUBLE_EQ(a.outlets.fraction(1) + a.outlets.fraction(2), 1.0);
}

TEST(Evaluation, IdealDisplacementFailsNeverAndEndsInTheTopLambdaOfO4) {
  std::vector<CellTrack> cells;
  cells.reserve(3);
  for (int k = 0; k < 3; ++k) {
    cells.push_back(
        track(k, 3.0, 1.0 + 10.0 * k, 101, [](double c) { return kD * c + wiggle(c); }));
  }
  const RunAnalysis a = analyze_run(run_of(cells), 100, kDisplacement);
  EXPECT_NEAR(a.p_f.mean, 0.0, kInterpolation);
  EXPECT_EQ(a.outlets.count[4], 3);
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    EXPECT_EQ(a.cells[k].mode, TransportMode::kDisplacement);
    EXPECT_GE(a.cells[k].y_end, a.bins.edges[4] - kLambda);
    EXPECT_LE(a.cells[k].y_end, a.bins.edges[4]);
  }
}

TEST(Evaluation, OneMissedDisplacementEveryKPillars) {
  // Displaced at every column but every k-th: y(N) = y0 + (N - N/k) d, so p_fD = d / (k lambda).
  for (int k : {2, 4, 5}) {
    const auto f = [k](double c) {
      const double missed = std::floor(steps(c) / k);  // whole columns at which it stayed
      return kD * (steps(c) - missed);
    };
    const RunAnalysis a =
        analyze_run(run_of({track(0, 0.0, 5.0, 100.2, f, 4000)}), 100, kDisplacement);
    EXPECT_NEAR(a.cells[0].p_f.value(), kD / (k * kLambda), 1e-9) << "k = " << k;
  }
}

TEST(Evaluation, OneBumpEveryKPillarsOfAZigzagCell) {
  // Bumped up by d once every k columns: p_fZ = d / (k lambda); bumped down gives the negative.
  for (int k : {3, 10}) {
    for (double sign : {1.0, -1.0}) {
      const auto f = [k, sign](double c) { return sign * kD * std::floor(steps(c) / k); };
      const RunAnalysis a = analyze_run(run_of({track(0, 0.0, 5.0, 60.5, f, 4000)}), 60, kZigzag);
      EXPECT_NEAR(a.cells[0].p_f.value(), sign * kD / (k * kLambda), 1e-9) << "k = " << k;
    }
  }
}

TEST(Evaluation, AStudyOfTwentyPillarsEvaluatesAndBinsAtTwenty) {
  // The headline's N = 20 (issue 16): two cells displaced at every column for 20 columns, then
  // moving horizontally for 40 more. At N = 20 neither fails and both end in O4's top lambda with
  // the bins of N = 20 ([y_in - 2 lambda, y_in + 20 d + lambda]); at N = 60 both fail with p_fD =
  // (40/60) d / lambda and end far below the N = 60 bins' top.
  const auto f = [](double c) { return kD * std::min(steps(c), 20.0) + wiggle(c); };
  const std::vector<CellTrack> cells{track(0, 3.0, 1.0, 60.5, f, 6000),
                                     track(1, 3.0, 11.0, 60.5, f, 6000)};
  const RunAnalysis at20 = analyze_run(run_of(cells), 20, kDisplacement);
  EXPECT_EQ(at20.outlet_pillars, 20);
  EXPECT_NEAR(at20.bins.edges[4] - at20.bins.edges[0], 20 * kD + 3 * kLambda, 1e-9);
  EXPECT_NEAR(at20.p_f.mean, 0.0, kInterpolation);
  EXPECT_EQ(at20.outlets.count[4], 2);
  for (const auto& c : at20.cells) {
    EXPECT_EQ(c.pillars, 20);
    EXPECT_GE(c.y_end, at20.bins.edges[4] - kLambda);
  }
  const RunAnalysis at60 = analyze_run(run_of(cells), 60, kDisplacement);
  EXPECT_NEAR(at60.bins.edges[4] - at60.bins.edges[0], 60 * kD + 3 * kLambda, 1e-9);
  EXPECT_NEAR(at60.p_f.mean, (40.0 / 60.0) * kD / kLambda, kInterpolation);
  EXPECT_LT(at60.cells[0].y_end, at60.bins.edges[4] - kLambda);
}

TEST(Evaluation, HorizontalMotionIsTheDisplacementCeiling) {
  for (double d : {2.0, 6.0}) {
    const RunAnalysis a = analyze_run(
        run_of({track(0, 0.0, 5.0, 100.5, [](double) { return 0.0; })}, d), 100, kDisplacement);
    EXPECT_NEAR(a.cells[0].p_f.value(), d / kLambda, 1e-12);
  }
}

TEST(Evaluation, MeanAndSampleStandardDeviationOverCells) {
  // Two zigzag cells bumped every 2 and every 4 columns: p_fZ = d/(2 lambda) and d/(4 lambda).
  const auto every = [](int k) { return [k](double c) { return kD * std::floor(steps(c) / k); }; };
  const RunAnalysis a = analyze_run(
      run_of({track(0, 0.0, 5.0, 40.5, every(2), 4000), track(1, 0.0, 9.0, 40.5, every(4), 4000)}),
      40, kZigzag);
  const double p1 = kD / (2 * kLambda), p2 = kD / (4 * kLambda);
  EXPECT_NEAR(a.p_f.mean, 0.5 * (p1 + p2), 1e-9);
  EXPECT_NEAR(a.p_f.std, std::abs(p1 - p2) / std::sqrt(2.0), 1e-9);
}

TEST(Evaluation, ShortCellIsEvaluatedAtTheWholeColumnsItPassed) {
  const RunAnalysis a =
      analyze_run(run_of({track(0, 0.0, 5.0, 12.7, [](double c) { return kD * c; }),
                          track(1, 0.0, 9.0, 30.2, [](double) { return 0.0; })}),
                  20, kDisplacement);
  EXPECT_EQ(a.cells[0].pillars, 12);
  EXPECT_EQ(a.cells[0].columns, 12);
  EXPECT_EQ(a.cells[1].pillars, 20);
  EXPECT_NEAR(a.cells[0].y_end, 5.0 + 12 * kD, 1e-9);
  EXPECT_EQ(a.outlet_pillars, 12);
  ASSERT_FALSE(a.notes.empty());
  EXPECT_NE(a.notes.front().find("evaluated at 12 pillars"), std::string::npos);
}

TEST(Evaluation, TheRunsExtentIsItsLastStepSlowestCellAndLargestVolumeChange) {
  CellTrack fast = track(
      0, 0.0, 5.0, 30.2, [](double) { return 0.0; }, 400);
  CellTrack slow = track(
      1, 0.0, 9.0, 21.5, [](double) { return 0.0; }, 300);
  fast.volume[200] = 94.0 * 0.99;  // -1 % once, back afterwards
  slow.volume[150] = 94.0 * 1.004;
  const RunAnalysis a = analyze_run(run_of({fast, slow}), 20, kZigzag);
  EXPECT_DOUBLE_EQ(a.last_step, 100.0 * 400);
  EXPECT_NEAR(a.slowest_advance, 21.5, 1e-9);
  EXPECT_NEAR(a.volume_change, 0.01, 1e-12);
}

TEST(Evaluation, NoFailureProbabilityWithoutAnExpectedMode) {
  const RunAnalysis a =
      analyze_run(run_of({track(0, 0.0, 5.0, 10.5, [](double c) { return wiggle(c); })}), 10,
                  ExpectedMode{TransportMode::kMixed, "test"});
  EXPECT_FALSE(a.cells[0].p_f.has_value());
  EXPECT_EQ(a.p_f.n, 0);
}

TEST(Outlets, FourEqualBinsOverTheSpecRange) {
  // N d + 3 lambda wide, from y_in - 2 lambda (SPEC section 7).
  const OutletBins b = outlet_bins(32.0, kLambda, 2.0, 100);
  EXPECT_DOUBLE_EQ(b.edges[0], 32.0 - 64.0);
  EXPECT_DOUBLE_EQ(b.edges[4], 32.0 + 200.0 + 32.0);
  EXPECT_DOUBLE_EQ(b.edges[2] - b.edges[1], (200.0 + 96.0) / 4);
  EXPECT_EQ(outlet_of(b, -40.0), 0);
  EXPECT_EQ(outlet_of(b, b.edges[1] - 1e-9), 1);
  EXPECT_EQ(outlet_of(b, b.edges[1]), 2);
  EXPECT_EQ(outlet_of(b, b.edges[4]), 4);
  EXPECT_EQ(outlet_of(b, b.edges[4] + 1e-9), 5);
  EXPECT_DOUBLE_EQ(inlet_band_bottom({40.0, 50.0}, kLambda), 32.0);
  EXPECT_DOUBLE_EQ(inlet_band_bottom({-3.0, 1.0}, kLambda), -32.0);
  const OutletCounts c = count_outlets(b, {-100.0, 0.0, 100.0, 150.0});
  EXPECT_EQ(c.count[0], 1);
  EXPECT_DOUBLE_EQ(c.fraction(2), 0.25);
}

}  // namespace
}  // namespace dld::analysis
