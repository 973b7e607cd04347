// SPDX-License-Identifier: MIT
// Mesh output ([output] mesh_every, membrane/mesh_output): the node positions land in the part
// file sample by sample in the stated layout, the XDMF beside it names exactly the stored samples
// and datasets (checked by tests/membrane/check_xdmf.py the way a reader follows it), a resumed
// run keeps the samples up to its checkpoint, and a coupled run writes its first sample at the
// cells' initial nodes, or nothing when the key is off.
#include "membrane/mesh_output.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "membrane/cells_part_file.hpp"
#include "membrane/membrane_scene.hpp"
#include "test_meshes.hpp"
#include "tests/child_process.hpp"
#include "tests/temp_dir.hpp"

namespace dld::membrane {
namespace {

namespace fs = std::filesystem;
// Child processes and temp dirs; test:: here is test_meshes.hpp's.
namespace dt = dld::test;

bool have_h5py() {
  return std::system("/usr/bin/python3 -c 'import h5py' > /dev/null 2>&1") == 0;
}

/// check_xdmf.py's output (last line: its verdict) and exit code.
std::pair<int, std::string> check_xdmf(const fs::path& xmf) {
  const fs::path out = xmf.string() + ".check";
  const std::string cmd = "/usr/bin/python3 " + std::string(DLD_SOURCE_DIR) +
                          "/tests/membrane/check_xdmf.py " + xmf.string() + " > " + out.string() +
                          " 2>&1";
  const int status = std::system(cmd.c_str());
  return {status, dt::slurp(out.string())};
}

/// Node positions of `cells` octahedra, distinct per sample so that a mix-up shows.
Points nodes_of_sample(int cells, int sample) {
  const TriMesh m = test::octahedron();
  Points x(3, cells * m.node_count());
  for (int k = 0; k < cells; ++k)
    x.middleCols(k * m.node_count(), m.node_count()) =
        (m.nodes * (1.0 + 0.1 * sample)).colwise() + Eigen::Vector3d(10.0 * k + sample, 2, 3);
  return x;
}

RunFacts facts(int cells) {
  RunFacts r;
  r.cells = cells;
  r.dt_s = 1e-6;
  r.lambda_um = 32;
  r.row_shift_um = 4.4;
  r.scene_name = "t";
  return r;
}

TEST(MeshOutput, SamplesLandInTheStatedLayoutAndTheXdmfNamesThem) {
  dt::TempDir dir("dld-mesh");
  const fs::path h5 = dir.path() / "run-cells-0.h5";
  const TriMesh m = test::octahedron();  // 6 nodes, 8 faces
  {
    H5File f(h5.string(), H5File::Mode::kCreate);
    MeshOutput out(f, m, 2, 3, 1e-6);
    EXPECT_EQ(out.xdmf_path(), (dir.path() / "run-cells-0.xmf").string());
    for (int i = 0; i < 3; ++i) out.append(10 * i, nodes_of_sample(2, i));
  }
  H5File f(h5.string(), H5File::Mode::kRead);
  std::vector<std::uint64_t> d;
  const auto x = f.read("/cells/mesh/positions", &d);
  ASSERT_EQ(d, (std::vector<std::uint64_t>{3, 12, 3}));
  const Points x1 = nodes_of_sample(2, 1);
  for (int n = 0; n < 12; ++n)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(x[(12 + n) * 3 + c], x1(c, n)) << n << " " << c;
  const auto faces = f.read("/cells/mesh/faces", &d);
  ASSERT_EQ(d, (std::vector<std::uint64_t>{16, 3}));
  // The second cell's faces are the first's, shifted by its 6 nodes.
  for (int i = 0; i < 24; ++i) EXPECT_EQ(faces[24 + i], faces[i] + 6) << i;
  EXPECT_EQ(f.read("/cells/mesh/cell"), (std::vector<double>{3, 3, 3, 3, 3, 3, 4, 4, 4, 4, 4, 4}));
  EXPECT_EQ(f.read("/cells/mesh/steps"), (std::vector<double>{0, 10, 20}));
  const auto t = f.read("/cells/mesh/time_s");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_DOUBLE_EQ(t[2], 20e-6);

  ASSERT_TRUE(fs::exists(dir.path() / "run-cells-0.xmf"));
  EXPECT_FALSE(fs::exists(dir.path() / "run-cells-0.xmf.tmp"));
  const std::string xmf = dt::slurp((dir.path() / "run-cells-0.xmf").string());
  EXPECT_NE(xmf.find("run-cells-0.h5:/cells/mesh/sample/0"), std::string::npos) << xmf;
  EXPECT_EQ(xmf.find(dir.path().string()), std::string::npos) << "the h5 is named relative";
  if (!have_h5py()) GTEST_SKIP() << "python3-h5py (Debian) not installed";
  const auto [status, report] = check_xdmf(dir.path() / "run-cells-0.xmf");
  EXPECT_EQ(status, 0) << report;
  EXPECT_NE(report.find("grids 3\n"), std::string::npos) << report;
  EXPECT_NE(report.find("grid 0 0 0\n"), std::string::npos) << report;
  EXPECT_NE(report.find("grid 20 "), std::string::npos) << report;
}

TEST(MeshOutput, CheckerRefusesAnXdmfThatDisagreesWithTheFile) {
  // The checker used above must be able to fail: an XDMF that states one sample too many.
  if (!have_h5py()) GTEST_SKIP() << "python3-h5py (Debian) not installed";
  dt::TempDir dir("dld-mesh");
  const fs::path h5 = dir.path() / "p.h5";
  {
    H5File f(h5.string(), H5File::Mode::kCreate);
    MeshOutput out(f, test::octahedron(), 1, 0, 1e-6);
    out.append(0, nodes_of_sample(1, 0));
  }
  std::ofstream(dir.path() / "p.xmf")
      << mesh_xdmf("p.h5", 6, 8, {MeshSample{0, 0.0}, MeshSample{5, 5e-6}});
  const auto [status, report] = check_xdmf(dir.path() / "p.xmf");
  EXPECT_NE(status, 0) << report;
  EXPECT_NE(report.find("p.h5 has no dataset /cells/mesh/sample/1"), std::string::npos) << report;
}

TEST(MeshOutput, ResumedPartKeepsTheMeshesUpToTheCheckpoint) {
  // A run that wrote samples at 0, 10, 20, resumed from its checkpoint at step 10: the new part
  // file holds the samples 0 and 10 of the old one, and appends 20 again after them.
  dt::TempDir dir("dld-mesh");
  const std::string path = (dir.path() / "run-cells-0.h5").string();
  const TriMesh m = test::octahedron();
  const std::vector<double> rows{0, 1, 2, 3, 4, 10, 1.5, 2, 3, 4, 20, 2, 2, 3, 4};
  {
    CellsPartFile part(path, facts(1), {}, std::nullopt);
    MeshOutput out(part.file(), m, 1, 0, 1e-6);
    for (int i = 0; i < 3; ++i) {
      part.append(std::vector<double>(rows.begin() + 5 * i, rows.begin() + 5 * i + 5));
      out.append(10 * i, nodes_of_sample(1, i));
    }
  }
  {
    CellsPartFile part(path, facts(1), std::vector<double>(rows.begin(), rows.begin() + 10), 10);
    MeshOutput out(part.file(), m, 1, 0, 1e-6);
    ASSERT_EQ(out.samples().size(), 2u);
    EXPECT_EQ(out.samples().back().step, 10);
    const std::string xmf = dt::slurp(out.xdmf_path());
    EXPECT_EQ(xmf.find("step 20"), std::string::npos) << "rewritten at once, without step 20";
    part.append(std::vector<double>(rows.begin() + 10, rows.end()));
    out.append(20, nodes_of_sample(1, 7));
  }
  H5File f(path, H5File::Mode::kRead);
  std::vector<std::uint64_t> d;
  const auto x = f.read("/cells/mesh/positions", &d);
  ASSERT_EQ(d, (std::vector<std::uint64_t>{3, 6, 3}));
  EXPECT_EQ(x[0], nodes_of_sample(1, 0)(0, 0));
  EXPECT_EQ(x[18], nodes_of_sample(1, 1)(0, 0));
  EXPECT_EQ(x[36], nodes_of_sample(1, 7)(0, 0));
  EXPECT_EQ(f.read("/cells/mesh/steps"), (std::vector<double>{0, 10, 20}));
  EXPECT_EQ(f.read("/cells/samples", &d), rows);
  EXPECT_EQ(d, (std::vector<std::uint64_t>{3, 5}));
  EXPECT_EQ(f.read_attribute_number("/cells", "count"), 1.0);
}

// A coupled run (dld-fluid + dld-membrane over ipc), one 500-face cell at dx = 0.8 um.
class MeshOutputCoupled : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::string(DLD_FLUID_EXE).empty() || std::string(DLD_MEMBRANE_EXE).empty())
      GTEST_SKIP() << "fluid or membrane program not built";
  }
  std::string scene(const std::string& output_keys) {
    const std::string sc = (dir_.path() / "cell.toml").string();
    std::ofstream(sc)
        << "[scene]\nname = \"cell\"\n[geometry]\npillar_radius_um = 10.0\n"
           "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
           "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n[run]\nthreads = 1\n"
           "[output]\nfields = false\n"
        << output_keys
        << "[coupling]\ntimeout_s = 20\n"
           "[membrane]\nradius_um = 3.9\nmesh_faces = 500\nmodels = [\"skalak\", \"bending\", "
           "\"volume\"]\ncapillary_number = 0.2\nmesh_cache = \""
        << (dir_.path() / "meshes").string()
        << "\"\n[membrane.skalak]\narea_modulus_ref_lu = 0.5\n[membrane.bending]\nmodulus_rel = "
           "2.5e-3\n[membrane.volume]\nmodulus_rel = 1000.0\n[[cells.cell]]\n"
           "centre_um = [3.0, 3.0, 2.4]\n";
    return sc;
  }
  /// Runs `steps` steps, samples every 100; returns the part file.
  std::string run(const std::string& sc, int steps) {
    const std::string sock = "ipc://" + (dir_.path() / "sock").string();
    const std::string out = (dir_.path() / "cell-cells-0.h5").string();
    dt::Process fluid = dt::spawn({DLD_FLUID_EXE, sc, "--serve", sock, "--cells", "1"},
                                  (dir_.path() / "fluid.log").string());
    dt::Process cell = dt::spawn({DLD_MEMBRANE_EXE, sc, "--connect", sock, "--steps",
                                  std::to_string(steps), "--sample-every", "100", "-o", out},
                                 (dir_.path() / "cell.log").string());
    EXPECT_EQ(dt::wait_for(cell, 180), 0) << dt::slurp(cell.log);
    EXPECT_EQ(dt::wait_for(fluid, 30), 0) << dt::slurp(fluid.log);
    return out;
  }
  dt::TempDir dir_{"dld-mesh-coupled"};
};

TEST_F(MeshOutputCoupled, FirstSampleIsTheInitialNodesAndTheXdmfFollowsTheSamples) {
  const std::string sc = scene("mesh_every = 100\n");
  const std::string out = run(sc, 200);
  // The initial nodes, built here from the same scene (the mesh comes from the run's cache).
  const Scene s = load_scene(sc, false);
  const CellSet cells = build_cells(read_membrane_scene(s), s);
  const Points x0 = cells.positions() * s.lattice.dx_um;

  H5File f(out, H5File::Mode::kRead);
  std::vector<std::uint64_t> d;
  const auto x = f.read("/cells/mesh/positions", &d);
  ASSERT_EQ(d, (std::vector<std::uint64_t>{3, static_cast<std::uint64_t>(x0.cols()), 3}));
  double worst = 0, drift = 0;
  for (int n = 0; n < x0.cols(); ++n) {
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(x[3 * n + c] - x0(c, n)));
    drift += x[(2 * x0.cols() + n) * 3] - x0(0, n);
  }
  EXPECT_LT(worst, 1e-12) << "sample 0 against the initial nodes [um]";
  // The cell moved downstream by step 200, in um: the samples are not all the start.
  EXPECT_GT(drift / static_cast<double>(x0.cols()), 0.01);
  EXPECT_EQ(f.read("/cells/mesh/steps"), (std::vector<double>{0, 100, 200}));
  f.read("/cells/mesh/faces", &d);
  // One closed surface of genus 0: F = 2 (N - 2).
  EXPECT_EQ(d, (std::vector<std::uint64_t>{2 * (static_cast<std::uint64_t>(x0.cols()) - 2), 3}));
  f.read("/cells/samples", &d);
  EXPECT_EQ(d, (std::vector<std::uint64_t>{3, 5}));

  const fs::path xmf = dir_.path() / "cell-cells-0.xmf";
  ASSERT_TRUE(fs::exists(xmf));
  if (!have_h5py()) GTEST_SKIP() << "python3-h5py (Debian) not installed";
  const auto [status, report] = check_xdmf(xmf);
  EXPECT_EQ(status, 0) << report;
  EXPECT_NE(report.find("grids 3\n"), std::string::npos) << report;
}

TEST_F(MeshOutputCoupled, WithoutTheKeyNothingOfTheMeshIsWritten) {
  // An XDMF left by an earlier run with meshes goes: it would name meshes the new part lacks.
  std::ofstream(dir_.path() / "cell-cells-0.xmf") << "stale";
  const std::string out = run(scene(""), 100);
  H5File f(out, H5File::Mode::kRead);
  std::vector<std::uint64_t> d;
  f.read("/cells/samples", &d);
  EXPECT_EQ(d, (std::vector<std::uint64_t>{2, 5})) << "the samples are written as before";
  EXPECT_FALSE(f.exists("/cells/mesh"));
  EXPECT_FALSE(fs::exists(dir_.path() / "cell-cells-0.xmf"));
}

}  // namespace
}  // namespace dld::membrane
