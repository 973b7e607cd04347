// SPDX-License-Identifier: MIT
// tcp is authenticated by default (issue 18, item 3): the programs refuse tcp without CURVE keys
// and plain tcp beyond loopback; a keyless client, a made-up key pair and a wrong server key all
// get nothing in and are named in the fluid's log, while the run's own client still runs; dld-run
// over tcp makes the run's keys itself.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "tests/child_process.hpp"
#include "tests/temp_dir.hpp"

namespace {

using dld::test::Process;
using dld::test::slurp;
using dld::test::spawn;
using dld::test::wait_for;

class TcpSecurity : public ::testing::Test {
 protected:
  void SetUp() override { port_ = 30000 + static_cast<int>(getpid() % 2000) * 8; }
  std::string path(const std::string& name) const { return (tmp_.path() / name).string(); }
  std::string endpoint(const std::string& host = "127.0.0.1") const {
    return "tcp://" + host + ":" + std::to_string(port_);
  }
  std::string scene(const std::string& coupling = "") const {
    const std::string p = path("scene.toml");
    std::ofstream(p) << "[scene]\nname = \"tcp\"\n[geometry]\npillar_radius_um = 10.0\n"
                        "pillar_spacing_um = 32.0\ndepth_um = 4.8\nrow_shift_um = 4.4\n"
                        "[lattice]\ndx_um = 0.8\n[drive]\nreynolds = 0.1\n[run]\nlog_every = 100\n"
                        "[output]\nfields = false\nfile = \""
                     << path("run.h5") << "\"\n[coupling]\ntimeout_s = 10\n"
                     << coupling;
    return p;
  }
  /// Runs a program to its end; its exit code and its log.
  std::pair<int, std::string> run(const std::vector<std::string>& args, const std::string& log) {
    Process p = spawn(args, path(log));
    const int rc = wait_for(p, 60);
    return {rc, slurp(p.log)};
  }
  void keys(const std::vector<std::string>& stems) {
    std::vector<std::string> args{DLD_KEYS_EXE};
    for (const auto& s : stems) args.push_back(path(s));
    ASSERT_EQ(run(args, "keys.log").first, 0);
  }
  dld::test::TempDir tmp_{"dld-tcp"};
  int port_ = 0;
};

/// One line, naming what it must.
void expect_one_line_error(const std::pair<int, std::string>& r, const std::string& needle) {
  EXPECT_NE(r.first, 0) << r.second;
  EXPECT_NE(r.first, -1) << "hung: " << r.second;
  EXPECT_NE(r.second.find(needle), std::string::npos) << r.second;
  EXPECT_EQ(r.second.find("terminate called"), std::string::npos) << r.second;
}

TEST_F(TcpSecurity, TcpWithoutKeysIsRefusedAtStart) {
  const std::string sc = scene();
  expect_one_line_error(run({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--cells", "1"}, "f.log"),
                        "dld-fluid: --serve " + endpoint() + ": tcp needs CURVE keys");
  expect_one_line_error(
      run({DLD_TRACERS_EXE, sc, "--connect", endpoint(), "--count", "1"}, "t.log"),
      "dld-tracers: --connect " + endpoint() + ": tcp needs CURVE keys");
}

TEST_F(TcpSecurity, PlainTcpOnlyOnLoopback) {
  const std::string sc = scene();
  expect_one_line_error(
      run({DLD_FLUID_EXE, sc, "--serve", endpoint("0.0.0.0"), "--plain-tcp", "--cells", "1"},
          "f.log"),
      "is not a loopback address");
  keys({"fluid"});
  expect_one_line_error(run({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--plain-tcp", "--curve-key",
                             path("fluid.key"), "--cells", "1"},
                            "g.log"),
                        "--plain-tcp with CURVE key files");
}

TEST_F(TcpSecurity, BadKeyFilesAreNamed) {
  const std::string sc = scene();
  keys({"membrane"});
  std::ofstream(path("bad.key")) << "public-key = \"tooshort\"\n";
  expect_one_line_error(
      run({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--curve-key", path("bad.key"),
           "--curve-clients", path("membrane.pub"), "--cells", "1"},
          "f.log"),
      path("bad.key") + ": line 1: public-key: expected 40 Z85 characters");
  expect_one_line_error(
      run({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--curve-key", path("membrane.pub"),
           "--curve-clients", path("membrane.pub"), "--cells", "1"},
          "g.log"),
      path("membrane.pub") + ": no secret-key");
}

TEST_F(TcpSecurity, IntrudersGetNothingInAndAreNamedWhileTheRunRuns) {
  const std::string sc = scene();
  keys({"fluid", "membrane", "stranger", "other-fluid"});
  Process fluid = spawn({DLD_FLUID_EXE, sc, "--serve", endpoint(), "--curve-key", path("fluid.key"),
                         "--curve-clients", path("membrane.pub"), "--cells", "2"},
                        path("fluid.log"));
  const std::vector<std::string> tracer{DLD_TRACERS_EXE, sc,  "--connect", endpoint(),
                                        "--count",       "2", "--steps",   "200"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = tracer;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  // One intruder at a time (the fluid's PAIR socket takes one connection at a time), each until
  // the fluid has named it.
  const std::vector<std::pair<std::vector<std::string>, std::string>> intruders{
      {{"--plain-tcp"}, "no CURVE keys"},  // "offered no CURVE keys" or "no CURVE keys on its side"
      {{"--curve-key", path("stranger.key"), "--curve-server", path("fluid.pub")},
       "is not among the run's client keys"},
      {{"--curve-key", path("membrane.key"), "--curve-server", path("other-fluid.pub")},
       "does not decrypt"}};
  for (const auto& [args, why] : intruders) {
    Process p = spawn(with(args), path("intruder.log"));
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (slurp(fluid.log).find(why) == std::string::npos &&
           std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    kill(p.pid, SIGKILL);
    wait_for(p, 5);
  }
  const std::string before = slurp(fluid.log);
  for (const auto& [args, why] : intruders)
    EXPECT_NE(before.find(why), std::string::npos) << why << "\n" << before;
  EXPECT_EQ(before.find("coupled with"), std::string::npos) << "an intruder got in: " << before;
  // The run's own membrane program still gets in and runs to its end.
  const auto own = run(
      with({"--curve-key", path("membrane.key"), "--curve-server", path("fluid.pub")}), "own.log");
  EXPECT_EQ(own.first, 0) << own.second;
  EXPECT_EQ(wait_for(fluid, 30), 0) << slurp(fluid.log);
}

TEST_F(TcpSecurity, LauncherMakesTheRunsKeys) {
  const std::string sc = scene("transport = \"tcp\"\n");
  const auto r = run({DLD_RUN_EXE, sc, "--tracers", "2", "--steps", "200"}, "run.log");
  EXPECT_EQ(r.first, 0) << r.second;
  EXPECT_NE(r.second.find("--curve-key"), std::string::npos) << r.second;
  EXPECT_NE(r.second.find("--curve-clients"), std::string::npos) << r.second;
  const std::string fluid_log = slurp(path("run-fluid.log"));
  EXPECT_NE(fluid_log.find("coupled with"), std::string::npos) << fluid_log;
  EXPECT_EQ(fluid_log.find("refused"), std::string::npos) << fluid_log;
}

}  // namespace
