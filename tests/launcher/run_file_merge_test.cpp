// SPDX-License-Identifier: MIT
// The run file of a coupled run: merge_run_file copies every part, values and attributes, and
// writes nothing when a part is missing or unreadable; dld-run writes it after a run however the
// run ended, says in one line when it cannot, and dld-analyze reads it as it reads the parts. The
// dld-run tests start a copy of dld-run beside stand-in programs (shell scripts that only exit):
// the part files are made by the test, so the launcher's side is tested in a second.
#include "coupler/launcher/run_file_merge.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"
#include "tests/child_process.hpp"
#include "tests/temp_dir.hpp"

namespace dld::coupler {
namespace {

namespace fs = std::filesystem;
using dld::test::slurp;

/// A fluid part as dld-fluid writes one (root attribute, /scene attributes, a time-series table,
/// an int32 field) and a cells part as dld-membrane does (/cells/samples, /cells attributes), with
/// values that differ per part so a part copied to the wrong group shows.
void write_fluid_part(const std::string& path) {
  H5File f(path, H5File::Mode::kCreate);
  f.attribute("/", "scene_text", std::string("[scene]\nname = \"merge\"\n"));
  f.attribute("/scene", "dx_um", 0.8);
  for (int s = 0; s < 3; ++s) {
    f.append_row("/timeseries", {100.0 * s, 1e-7 * s, 0.25 + s}, {"step", "time_s", "u"});
  }
  const std::int32_t solid[6] = {0, 1, 1, 0, 0, 1};
  f.write("/fields/solid", solid, {2, 3});
}

void write_cells_part(const std::string& path, int first_cell, int cells) {
  H5File f(path, H5File::Mode::kCreate);
  const std::size_t width = 1 + 4 * static_cast<std::size_t>(cells);
  std::vector<double> rows;
  for (int s = 0; s < 4; ++s) {
    rows.push_back(500.0 * s);
    for (int c = 0; c < cells; ++c) {
      const double id = first_cell + c;
      rows.insert(rows.end(), {3.0 + 20 * s + id, 1.0 + 0.5 * s * id, 2.4, 94.0 - 0.01 * id});
    }
  }
  f.write("/cells/samples", rows.data(), {rows.size() / width, width});
  f.attribute("/cells", "count", static_cast<std::int64_t>(cells));
  f.attribute("/cells", "first_cell", static_cast<std::int64_t>(first_cell));
  f.attribute("/cells", "dt_s", 1e-7);
  f.attribute("/cells", "frame", std::string("device"));
  f.attribute("/cells", "pillar_spacing_um", 32.0);
  f.attribute("/cells", "row_shift_um", 4.4);
  f.attribute("/cells", "scene_name", std::string("merge"));
  f.attribute("/cells", "capillary_number", 0.2);
}

/// The parts of run `stem`: a fluid part and two cells parts (cells 0, 1 and cell 2).
void write_parts(const std::string& stem) {
  write_fluid_part(stem + "-fluid.h5");
  write_cells_part(stem + "-cells-0.h5", 0, 2);
  write_cells_part(stem + "-cells-1.h5", 2, 1);
}

/// Every dataset of every part is in the run file under the part's group, with the same shape
/// and values, and the run file holds nothing else.
void expect_parts_copied(const std::vector<RunPart>& parts, const std::string& merged) {
  const H5File m(merged, H5File::Mode::kRead);
  std::vector<std::string> expected;
  for (const RunPart& p : parts) {
    const H5File part(p.file, H5File::Mode::kRead);
    const auto names = part.datasets();
    ASSERT_FALSE(names.empty()) << p.file;
    for (const std::string& d : names) {
      expected.push_back(p.group + "/" + d);
      std::vector<std::uint64_t> dims_part, dims_merged;
      const auto a = part.read("/" + d, &dims_part);
      const auto b = m.read("/" + p.group + "/" + d, &dims_merged);
      EXPECT_EQ(dims_part, dims_merged) << p.group << "/" << d;
      EXPECT_EQ(a, b) << p.group << "/" << d;
    }
    EXPECT_EQ(m.read_attribute_string("/" + p.group, "source_file"),
              fs::path(p.file).filename().string());
  }
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(m.datasets(), expected);
}

TEST(RunFileMerge, HoldsExactlyTheDatasetsAndAttributesOfTheParts) {
  test::TempDir dir("dld-merge");
  const std::string stem = (dir.path() / "run").string(), merged = stem + ".h5";
  write_parts(stem);
  const auto parts = run_parts(stem, "cells", 2);
  ASSERT_EQ(parts.size(), 3u);
  EXPECT_EQ(parts[2].group, "membrane-1");
  EXPECT_EQ(parts[2].file, stem + "-cells-1.h5");
  merge_run_file(parts, merged);
  expect_parts_copied(parts, merged);
  const H5File m(merged, H5File::Mode::kRead);
  // Attributes come along: the fluid file's root, its groups and tables, the cells' geometry.
  EXPECT_EQ(m.read_attribute_string("/fluid", "scene_text"), "[scene]\nname = \"merge\"\n");
  EXPECT_EQ(m.read_attribute_number("/fluid/scene", "dx_um"), 0.8);
  EXPECT_EQ(m.read_attribute_string("/fluid/timeseries", "columns"), "step,time_s,u");
  EXPECT_EQ(m.read_attribute_number("/membrane-1/cells", "first_cell"), 2.0);
  EXPECT_EQ(m.read_attribute_number("/membrane-0/cells", "count"), 2.0);
  EXPECT_EQ(m.read_attribute_number("/", "membrane_processes"), 2.0);
  EXPECT_FALSE(fs::exists(merged + ".tmp"));
}

TEST(RunFileMerge, AMissingOrUnreadablePartWritesNothingAndSaysWhichOne) {
  test::TempDir dir("dld-merge");
  const std::string stem = (dir.path() / "run").string(), merged = stem + ".h5";
  write_parts(stem);
  std::ofstream(merged) << "an earlier run file\n";
  const auto expect_refused = [&](const std::string& part, const std::string& words) {
    std::string error;
    try {
      merge_run_file(run_parts(stem, "cells", 2), merged);
    } catch (const InputError& e) {
      error = e.what();
    }
    EXPECT_NE(error.find(part + ": " + words), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(slurp(merged), "an earlier run file\n") << "the run file is replaced only whole";
    EXPECT_FALSE(fs::exists(merged + ".tmp"));
  };
  fs::remove(stem + "-cells-1.h5");
  expect_refused(stem + "-cells-1.h5", "no such file (expected the membrane-1 part of the run)");
  std::ofstream(stem + "-cells-1.h5") << "cut short by a crash\n";
  expect_refused(stem + "-cells-1.h5", "cannot open HDF5 file");
}

/// dld-run copied into a directory beside stand-ins for dld-fluid and dld-membrane (it looks for
/// its programs next to itself first); each stand-in exits with the code in `<name>.code`.
class DldRunMerge : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::copy_file(DLD_RUN_EXE, bin() / "dld-run");
    for (const char* name : {"dld-fluid", "dld-membrane"}) {
      const fs::path script = bin() / name;
      // <name>.say: lines it prints first; <name>.sleep: seconds it then waits (a slow start).
      const std::string at = (bin() / name).string();
      std::ofstream(script) << "#!/bin/sh\n[ -f " << at << ".say ] && cat " << at << ".say\n[ -f "
                            << at << ".sleep ] && sleep $(cat " << at << ".sleep)\nexit $(cat "
                            << at << ".code)\n";
      fs::permissions(script, fs::perms::owner_all);
      exit_code(name, 0);
    }
    scene_ = (dir_.path() / "scene.toml").string();
    std::ofstream(scene_) << "[scene]\nname = \"merge\"\n[geometry]\npillar_radius_um = 10.0\n"
                             "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
                             "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n"
                             "[output]\nfields = false\nfile = \""
                          << stem() << ".h5\"\n[coupling]\nmembrane_processes = 2\n"
                          << "[[cells.cell]]\ncentre_um = [3.0, 3.0, 2.4]\n"
                             "[[cells.cell]]\ncentre_um = [20.0, 3.0, 2.4]\n";
  }
  fs::path bin() const { return dir_.path(); }
  std::string stem() const { return (dir_.path() / "run").string(); }
  void exit_code(const std::string& program, int code) {
    std::ofstream(bin() / (program + ".code")) << code << "\n";
  }
  /// Runs dld-run on the scene; its exit code and output.
  std::pair<int, std::string> run() {
    const std::string log = (dir_.path() / "dld-run.log").string();
    const auto p = test::spawn({(bin() / "dld-run").string(), scene_, "--membrane", "cells"}, log);
    const int code = test::wait_for(p, 30);
    return {code, slurp(log)};
  }
  void say(const std::string& program, const std::string& lines) {
    std::ofstream(bin() / (program + ".say")) << lines;
  }
  test::TempDir dir_{"dld-run-merge"};
  std::string scene_;
};

// dld-run's temporary folder (its sockets) is gone after a dry run, a failed run and a good one.
TEST_F(DldRunMerge, LeavesNoTemporaryFolderBehind) {
  for (const std::string how : {"dry", "failed", "done"}) {
    exit_code("dld-fluid", how == "failed" ? 1 : 0);
    if (how == "done") write_parts(stem());
    std::vector<std::string> args{(bin() / "dld-run").string(), scene_, "--membrane", "cells"};
    if (how == "dry") args.push_back("--dry-run");
    const std::string log = (dir_.path() / "dld-run.log").string();
    const auto p = test::spawn(args, log);
    EXPECT_EQ(test::wait_for(p, 30) == 0, how != "failed") << how << ": " << slurp(log);
    EXPECT_FALSE(fs::exists(fs::temp_directory_path() / ("dld-run-" + std::to_string(p.pid))))
        << how;
  }
}

// An [output] file that is a directory (empty or not) is refused before anything runs, and left
// as it was (it used to be removed, or to give an error line and exit code 0).
TEST_F(DldRunMerge, AnOutputPathThatIsADirectoryIsRefused) {
  for (const bool empty : {true, false}) {
    fs::create_directories(stem() + ".h5");
    if (!empty) std::ofstream(stem() + ".h5/keep") << "x";
    const auto [code, out] = run();
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("[output] file '" + stem() + ".h5' is a directory"), std::string::npos)
        << out;
    EXPECT_TRUE(fs::is_directory(stem() + ".h5"));
    EXPECT_EQ(fs::exists(stem() + ".h5/keep"), !empty);
    fs::remove_all(stem() + ".h5");
  }
}

TEST_F(DldRunMerge, WritesTheRunFileAndNamesItInTheLastLine) {
  write_parts(stem());
  const auto [code, out] = run();
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("dld-run: done in"), std::string::npos) << out;
  EXPECT_NE(out.find("run file " + stem() + ".h5, parts"), std::string::npos) << out;
  // Two cells over two membrane processes: their contact goes through the halo, no warning.
  EXPECT_EQ(out.find("warning"), std::string::npos) << out;
  expect_parts_copied(run_parts(stem(), "cells", 2), stem() + ".h5");
  // The parts stay: --resume continues them.
  EXPECT_TRUE(fs::exists(stem() + "-cells-1.h5"));
#ifdef DLD_ANALYZE_EXE
  // dld-analyze gives the same tables from the run file as from the parts.
  const auto analyze = [&](const std::string& files, const std::string& out_dir) {
    const std::string log = (dir_.path() / (out_dir + ".log")).string();
    const auto p = test::spawn({"/bin/sh", "-c",
                                std::string(DLD_ANALYZE_EXE) + " " + files +
                                    " --pillars 1 --expected-mode displacement --no-plots -o " +
                                    (dir_.path() / out_dir).string()},
                               log);
    EXPECT_EQ(test::wait_for(p, 30), 0) << slurp(log);
    return slurp((dir_.path() / out_dir / "run-summary.csv").string());
  };
  const std::string from_parts = analyze(stem() + "-cells-0.h5 " + stem() + "-cells-1.h5", "a");
  EXPECT_NE(from_parts.find("\"merge\",32,4.4,0.2,3,"), std::string::npos)
      << from_parts;  // 3 cells
  EXPECT_EQ(analyze(stem() + ".h5", "b"), from_parts);
#endif
}

TEST_F(DldRunMerge, AfterAFailureTheRunFileHoldsWhatWasWrittenAndTheExitCodeIsTheRuns) {
  write_parts(stem());
  exit_code("dld-membrane", 3);
  const auto [code, out] = run();
  EXPECT_EQ(code, 3) << out;
  EXPECT_NE(out.find("holds what the programs wrote before the failure"), std::string::npos) << out;
  expect_parts_copied(run_parts(stem(), "cells", 2), stem() + ".h5");
}

TEST_F(DldRunMerge, AMissingPartIsOneLineAndNoRunFile) {
  write_parts(stem());
  fs::remove(stem() + "-cells-1.h5");
  // One from an earlier run must not stand for this one.
  std::ofstream(stem() + ".h5") << "an earlier run file\n";
  const auto [code, out] = run();
  EXPECT_EQ(code, 0) << out;  // the programs ended normally: the run's status
  const std::string line = "dld-run: run file " + stem() + ".h5 not written: " + stem() +
                           "-cells-1.h5: no such file (expected the membrane-1 part of the run) "
                           "(the part files stay)\n";
  EXPECT_NE(out.find(line), std::string::npos) << out;
  EXPECT_NE(out.find("run file not written, parts"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(stem() + ".h5"));
  // And with the failure of a program: its exit code, the same line.
  exit_code("dld-fluid", 4);
  const auto [failed_code, failed_out] = run();
  EXPECT_EQ(failed_code, 4) << failed_out;
  EXPECT_NE(failed_out.find(line), std::string::npos) << failed_out;
}

// The line relayed for a failed program is its error line, not whatever it printed last (issue 18,
// item 5: "stopped with exit code 3:   lattice body force: ...").
TEST_F(DldRunMerge, AFailedProgramIsReportedByItsErrorLine) {
  say("dld-fluid",
      "[dld-fluid] scene resolved\n[dld-fluid] error: the lattice is not finite\n"
      "  lattice body force: f_x 0.0001\n");
  exit_code("dld-fluid", 3);
  const auto [code, out] = run();
  EXPECT_EQ(code, 3) << out;
  EXPECT_NE(out.find("dld-fluid stopped with exit code 3: [dld-fluid] error: the lattice is not "
                     "finite"),
            std::string::npos)
      << out;
}

// A membrane program that fails at start-up stops the run at once: the fluid, still waiting for
// its hellos, is not left to its handshake timeout.
TEST_F(DldRunMerge, AMembraneThatFailsAtStartUpStopsTheRunAtOnce) {
  std::ofstream(bin() / "dld-fluid.sleep") << "60\n";
  say("dld-membrane", "dld-membrane: error: scene.toml: bad mesh\n");
  exit_code("dld-membrane", 1);
  const auto t0 = std::chrono::steady_clock::now();
  const auto [code, out] = run();
  EXPECT_NE(code, 0) << out;
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10)) << out;
  EXPECT_NE(out.find("dld-membrane: error: scene.toml: bad mesh"), std::string::npos) << out;
}

// The other way round: a fluid that fails before the handshake (e.g. refusing a checkpoint) stops
// membrane programs still busy before their hello (packing cells) at once, not after the timeout.
TEST_F(DldRunMerge, AFluidThatFailsBeforeTheHandshakeStopsTheRunAtOnce) {
  std::ofstream(bin() / "dld-membrane.sleep") << "60\n";
  say("dld-fluid",
      "[dld-fluid] error: run-fluid.ckpt.h5: /fluid scene_hash a is not the scene's b\n");
  exit_code("dld-fluid", 3);
  const auto t0 = std::chrono::steady_clock::now();
  const auto [code, out] = run();
  EXPECT_EQ(code, 3) << out;
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10)) << out;
  EXPECT_NE(out.find("scene_hash a is not the scene's b"), std::string::npos) << out;
}

// --dry-run checks the membrane part too (dld-membrane --check): its refusal is dld-run's, exit 2.
TEST_F(DldRunMerge, DryRunRefusesAnInvalidMembranePart) {
  say("dld-membrane", "dld-membrane: error: scene.toml:12: 'membrane.mesh_faces': too few\n");
  exit_code("dld-membrane", 1);
  const std::string log = (dir_.path() / "dry.log").string();
  const auto p =
      test::spawn({(bin() / "dld-run").string(), scene_, "--membrane", "cells", "--dry-run"}, log);
  EXPECT_EQ(test::wait_for(p, 30), 2) << slurp(log);
  EXPECT_NE(slurp(log).find("error: dld-membrane: error: scene.toml:12: 'membrane.mesh_faces'"),
            std::string::npos)
      << slurp(log);
  exit_code("dld-membrane", 0);
  const auto ok =
      test::spawn({(bin() / "dld-run").string(), scene_, "--membrane", "cells", "--dry-run"}, log);
  EXPECT_EQ(test::wait_for(ok, 30), 0) << slurp(log);
}

// Bad placement (issue 14): one error line naming the option, exit 2, before anything starts.
TEST_F(DldRunMerge, BadPlacementIsOneLineNamingTheOption) {
  const std::string log = (dir_.path() / "place.log").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--hosts", "a,b,c", "--membrane-processes", "2"}, "--hosts: 3 hosts for 2 membrane"},
      {{"--hosts", "a", "--start-with", "ssh"},
       "--start-with 'ssh': expected a command with {host}"},
      {{"--start-with", "ssh {host}"},
       "--start-with and --fluid-host place membrane processes on --hosts: expected --hosts too"},
      {{"--hosts", "a,b", "--membrane-processes", "2", "--start-with", "ssh {host}", "--port",
        "65535"},
       "--port 65535: 2 membrane processes need ports 65535 to 65536"}};
  for (const auto& [args, message] : cases) {
    std::vector<std::string> argv{(bin() / "dld-run").string(), scene_, "--membrane", "cells",
                                  "--dry-run"};
    argv.insert(argv.end(), args.begin(), args.end());
    EXPECT_EQ(test::wait_for(test::spawn(argv, log), 30), 2) << slurp(log);
    EXPECT_NE(slurp(log).find("error: " + message), std::string::npos) << slurp(log);
  }
}

// --resume names each checkpoint it cannot use and why: a corrupt file is not a missing one.
TEST_F(DldRunMerge, ResumeTellsACorruptCheckpointFromAMissingOne) {
  std::ofstream(stem() + "-fluid.ckpt.h5") << "cut short by a crash\n";
  const std::string log = (dir_.path() / "resume.log").string();
  const auto p =
      test::spawn({(bin() / "dld-run").string(), scene_, "--membrane", "cells", "--resume"}, log);
  EXPECT_EQ(test::wait_for(p, 30), 2) << slurp(log);
  const std::string out = slurp(log);
  EXPECT_NE(out.find(stem() + "-fluid.ckpt.h5 (not a readable checkpoint)"), std::string::npos)
      << out;
  EXPECT_NE(out.find(stem() + "-cells-0.ckpt.h5 (no such file)"), std::string::npos) << out;
}

}  // namespace
}  // namespace dld::coupler
