// SPDX-License-Identifier: MIT
// Reading and merging cells run files (the layout of membrane/coupled_main.cpp), and the one-line
// errors for bad input.
#include "analysis/run_file.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "shared/dld_geometry.hpp"
#include "shared/input_error.hpp"
#include "synthetic.hpp"

namespace dld::analysis {
namespace {

using testing::error_of;
using testing::FileFacts;
using testing::track;
using testing::write_run_file;

CellTrack line(int id, double y0, double slope) {
  return track(
      id, 2.0, y0, 5.0, [slope](double c) { return slope * c; }, 50);
}

TEST(RunFile, StemDropsTheCellsSuffix) {
  EXPECT_EQ(run_stem("runs/a-b-cells-12.h5"), "runs/a-b");
  EXPECT_EQ(run_stem("runs/other.h5"), "runs/other");
}

TEST(RunFile, ReadsWhatWasWritten) {
  const std::string dir = testing::temp_dir("read");
  const std::string path = dir + "/run-cells-0.h5";
  write_run_file(path, {line(0, 1.0, 4.4), line(1, 7.0, 0.0)}, {.first_cell = 0, .d = 4.4});
  const analysis::Run r = read_run_file(path);
  EXPECT_EQ(r.stem, dir + "/run");
  EXPECT_EQ(r.scene_name, "synthetic");
  EXPECT_DOUBLE_EQ(r.lambda_um, 32.0);
  EXPECT_DOUBLE_EQ(r.row_shift_um, 4.4);
  ASSERT_TRUE(r.capillary_number.has_value());
  EXPECT_DOUBLE_EQ(*r.capillary_number, 0.5);
  ASSERT_EQ(r.cells.size(), 2u);
  EXPECT_EQ(r.cells[1].id, 1);
  ASSERT_EQ(r.cells[1].position.size(), 51u);
  EXPECT_DOUBLE_EQ(r.cells[0].position.back()[1], 1.0 + 5 * 4.4);
  EXPECT_DOUBLE_EQ(r.cells[1].position.back()[0], 2.0 + 5 * 32.0);
  EXPECT_DOUBLE_EQ(r.cells[1].step[3], 300.0);
}

TEST(RunFile, BoxFrameFilesAreUnwrapped) {
  // A displaced cell (crossing x and y faces) stored folded into the box comes back unchanged.
  const std::string dir = testing::temp_dir("box");
  const CellTrack device = track(
      0, 3.0, 30.0, 6.0, [](double c) { return 4.4 * c + 1.5; }, 300);
  CellTrack box = device;
  const DldCell cell{32.0, 10.0, 4.8, 4.4};
  for (auto& p : box.position) {
    p = wrap_into_box(cell, p).position;
  }
  write_run_file(dir + "/run-cells-0.h5", {box}, {.d = 4.4});
  {
    H5File h(dir + "/run-cells-0.h5", H5File::Mode::kReadWrite);
    h.attribute("/cells", "frame", std::string("box"));
  }
  const analysis::Run r = read_run_file(dir + "/run-cells-0.h5");
  ASSERT_EQ(r.cells.size(), 1u);
  EXPECT_LT(box.position.back()[0] - device.position.back()[0], -100.0);  // it was folded
  for (std::size_t i = 0; i < device.position.size(); ++i) {
    EXPECT_NEAR(r.cells[0].position[i][0], device.position[i][0], 1e-9) << i;
    EXPECT_NEAR(r.cells[0].position[i][1], device.position[i][1], 1e-9) << i;
  }
}

TEST(RunFile, CapillaryNumberIsOptional) {
  const std::string path = testing::temp_dir("no-ca") + "/run-cells-0.h5";
  write_run_file(path, {line(0, 1.0, 0.0)}, {.with_ca = false});
  EXPECT_FALSE(read_run_file(path).capillary_number.has_value());
}

TEST(RunFile, ExpectedModeIsReadWhenTheSceneStatedIt) {
  const std::string dir = testing::temp_dir("mode");
  write_run_file(dir + "/none-cells-0.h5", {line(0, 1.0, 0.0)}, {});
  EXPECT_FALSE(read_run_file(dir + "/none-cells-0.h5").expected_mode.has_value());
  for (const auto mode : {TransportMode::kZigzag, TransportMode::kDisplacement}) {
    const std::string path = dir + "/" + to_string(mode) + "-cells-0.h5";
    write_run_file(path, {line(0, 1.0, 0.0)}, {.expected_mode = to_string(mode)});
    EXPECT_EQ(read_run_file(path).expected_mode, std::optional(mode)) << path;
  }
}

TEST(RunFile, MergesTheFilesOfOneRunByFirstCell) {
  const std::string dir = testing::temp_dir("merge");
  write_run_file(dir + "/run-cells-0.h5", {line(0, 1.0, 4.4), line(1, 5.0, 4.4)},
                 {.first_cell = 0});
  write_run_file(dir + "/run-cells-1.h5", {line(2, 9.0, 0.0)}, {.first_cell = 2});
  const analysis::Run r = read_run({dir + "/run-cells-1.h5", dir + "/run-cells-0.h5"});
  ASSERT_EQ(r.cells.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(r.cells[static_cast<std::size_t>(k)].id, k);
  }
  EXPECT_DOUBLE_EQ(r.cells[2].position.front()[1], 9.0);
  EXPECT_DOUBLE_EQ(r.cells[0].position.front()[1], 1.0);
  EXPECT_EQ(r.files.size(), 2u);
  // A checkpoint beside them (matched by the glob <stem>-cells-*.h5) is skipped, not read.
  std::ofstream(dir + "/run-cells-0.ckpt.h5") << "checkpoint\n";
  const analysis::Run with_ckpt =
      read_run({dir + "/run-cells-0.ckpt.h5", dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"});
  EXPECT_EQ(with_ckpt.cells.size(), 3u);
  ASSERT_EQ(with_ckpt.skipped.size(), 1u);
  EXPECT_NE(error_of([&] { read_run({dir + "/run-cells-0.ckpt.h5"}); }).find("a checkpoint"),
            std::string::npos);
}

TEST(RunFile, RefusesFilesOfDifferentRunsOrRepeatedCells) {
  const std::string dir = testing::temp_dir("merge-bad");
  write_run_file(dir + "/run-cells-0.h5", {line(0, 1.0, 0.0)}, {.first_cell = 0, .d = 4.4});
  write_run_file(dir + "/run-cells-1.h5", {line(1, 1.0, 0.0)}, {.first_cell = 1, .d = 6.0});
  write_run_file(dir + "/run-cells-2.h5", {line(0, 1.0, 0.0)}, {.first_cell = 0, .d = 4.4});
  EXPECT_NE(error_of([&] {
              read_run({dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"});
            }).find("row_shift_um"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              read_run({dir + "/run-cells-0.h5", dir + "/run-cells-2.h5"});
            }).find("cell 0 is also in"),
            std::string::npos);
  // One process's file says zigzag, the other's nothing: not the files of one scene.
  write_run_file(dir + "/run-cells-3.h5", {line(3, 1.0, 0.0)},
                 {.first_cell = 3, .d = 4.4, .expected_mode = "zigzag"});
  const std::string e = error_of([&] {
    read_run({dir + "/run-cells-0.h5", dir + "/run-cells-3.h5"});
  });
  EXPECT_NE(e.find("expected_mode = zigzag but"), std::string::npos) << e;
}

TEST(RunFile, TheMergedRunFileReadsAsItsParts) {
  const std::string dir = testing::temp_dir("merged");
  write_run_file(dir + "/run-cells-0.h5", {line(0, 1.0, 4.4), line(1, 5.0, 4.4)},
                 {.first_cell = 0});
  write_run_file(dir + "/run-cells-1.h5", {line(2, 9.0, 0.0)}, {.first_cell = 2});
  testing::write_merged_run_file(dir + "/run.h5",
                                 {dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"}, 2);
  const analysis::Run parts = read_run({dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"});
  const analysis::Run merged = read_run({dir + "/run.h5"});
  EXPECT_EQ(merged.stem, parts.stem);  // the outputs get the same names
  EXPECT_EQ(merged.files, std::vector<std::string>{dir + "/run.h5"});
  EXPECT_EQ(merged.scene_name, parts.scene_name);
  EXPECT_EQ(merged.row_shift_um, parts.row_shift_um);
  EXPECT_EQ(merged.capillary_number, parts.capillary_number);
  ASSERT_EQ(merged.cells.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(merged.cells[k].id, parts.cells[k].id);
    EXPECT_EQ(merged.cells[k].position, parts.cells[k].position) << k;
    EXPECT_EQ(merged.cells[k].volume, parts.cells[k].volume) << k;
  }
  // The run file and one of its parts hold the same cells: not two parts of one run.
  EXPECT_NE(error_of([&] {
              read_run({dir + "/run.h5", dir + "/run-cells-1.h5"});
            }).find("cell 2 is also in"),
            std::string::npos);
}

TEST(RunFile, AMergedRunFileMissingAGroupOrWithClashingGroupsIsRefused) {
  const std::string dir = testing::temp_dir("merged-bad");
  write_run_file(dir + "/run-cells-0.h5", {line(0, 1.0, 0.0)}, {.first_cell = 0});
  write_run_file(dir + "/run-cells-1.h5", {line(1, 1.0, 0.0)}, {.first_cell = 1, .d = 6.0});
  const auto expect_error = [](const std::string& path, const std::string& words) {
    const std::string e = error_of([&] { read_run_file(path); });
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find(words), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  // Two membrane processes stated, one group there: a cell would silently go missing.
  testing::write_merged_run_file(dir + "/short.h5", {dir + "/run-cells-0.h5"}, 2);
  expect_error(dir + "/short.h5", "1 /membrane-K/cells groups: expected 2");
  // Without the attribute the groups present are the run.
  testing::write_merged_run_file(dir + "/unstated.h5", {dir + "/run-cells-0.h5"}, -1);
  EXPECT_EQ(read_run_file(dir + "/unstated.h5").cells.size(), 1u);
  // Groups of different runs: the message names the group that disagrees.
  testing::write_merged_run_file(dir + "/clash.h5",
                                 {dir + "/run-cells-0.h5", dir + "/run-cells-1.h5"}, 2);
  expect_error(dir + "/clash.h5", "/membrane-1/cells: row_shift_um = 6 but");
  // A run file of dld-run --membrane tracers holds no cells.
  {
    H5File h(dir + "/tracers.h5", H5File::Mode::kCreate);
    h.write("/membrane-0/tracers/samples", std::vector<double>{0, 1, 2, 3});
    h.write("/fluid/timeseries", std::vector<double>{0, 1});
  }
  expect_error(dir + "/tracers.h5", "no /membrane-K/cells group");
}

TEST(RunFile, BadInputIsOneLineNamingTheFileAndWhatWasExpected) {
  const std::string dir = testing::temp_dir("bad");
  const auto expect_error = [](const std::string& path, const std::string& words) {
    const std::string e = error_of([&] { read_run_file(path); });
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find(words), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  };
  expect_error(dir + "/missing-cells-0.h5", "no such file");
  std::ofstream(dir + "/text-cells-0.h5") << "not hdf5\n";
  expect_error(dir + "/text-cells-0.h5", "cannot open HDF5 file");
  {
    H5File h(dir + "/empty-cells-0.h5", H5File::Mode::kCreate);
    h.write("/other", std::vector<double>{1.0});
  }
  expect_error(dir + "/empty-cells-0.h5", "/cells/samples");
  // Header says 2 cells, the table holds one.
  write_run_file(dir + "/cols-cells-0.h5", {line(0, 1.0, 0.0)}, {});
  {
    H5File h(dir + "/cols-cells-0.h5", H5File::Mode::kReadWrite);
    h.attribute("/cells", "count", std::int64_t{2});
  }
  expect_error(dir + "/cols-cells-0.h5", "expected (rows >= 1, 9)");
  // A missing attribute.
  {
    H5File h(dir + "/attr-cells-0.h5", H5File::Mode::kCreate);
    h.write("/cells/samples", std::vector<double>{0, 1, 2, 3, 4}.data(), {1, 5});
    h.attribute("/cells", "count", std::int64_t{1});
    h.attribute("/cells", "first_cell", std::int64_t{0});
    h.attribute("/cells", "dt_s", 1e-7);
  }
  expect_error(dir + "/attr-cells-0.h5", "pillar_spacing_um");
  write_run_file(dir + "/frame-cells-0.h5", {line(0, 1.0, 0.0)}, {});
  {
    H5File h(dir + "/frame-cells-0.h5", H5File::Mode::kReadWrite);
    h.attribute("/cells", "frame", std::string("lab"));
  }
  expect_error(dir + "/frame-cells-0.h5", "expected 'device' (or 'box')");
  // The scene's expected mode: a word that is not a mode, or not a string at all.
  write_run_file(dir + "/mode-cells-0.h5", {line(0, 1.0, 0.0)}, {.expected_mode = "mixed"});
  expect_error(dir + "/mode-cells-0.h5",
               "/cells expected_mode: 'mixed' is not a mode: expected zigzag or displacement");
  write_run_file(dir + "/mode-type-cells-0.h5", {line(0, 1.0, 0.0)}, {});
  {
    H5File h(dir + "/mode-type-cells-0.h5", H5File::Mode::kReadWrite);
    h.attribute("/cells", "expected_mode", 1.0);
  }
  expect_error(dir + "/mode-type-cells-0.h5", "/cells attribute 'expected_mode': expected a");
}

}  // namespace
}  // namespace dld::analysis
