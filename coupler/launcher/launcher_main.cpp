// SPDX-License-Identifier: MIT
// dld-run: validates a scene, starts dld-fluid and the membrane program(s) connected over ipc,
// shows their progress, and stops everything cleanly (Ctrl-C: the fluid is asked to end the run
// after the current step and tells every membrane program; a child that fails stops the others
// through the coupler's timeout, and the launcher reports which one failed and how). When they
// have ended, however they ended, it copies their part files into the run file (the scene's
// [output] file; coupler/launcher/run_file_merge).
//
// Membrane programs take: SCENE --connect ENDPOINT --peer k --peers K [program options].
#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>
#include <utility>

#include "coupler/curve_keys.hpp"
#include "coupler/launcher/checkpoints.hpp"
#include "coupler/launcher/exact_stretches.hpp"
#include "coupler/launcher/placement.hpp"
#include "coupler/launcher/process.hpp"
#include "coupler/launcher/run_file_merge.hpp"
#include "shared/cli_checks.hpp"
#include "shared/guarded_main.hpp"
#include "shared/h5file.hpp"
#include "shared/input_error.hpp"
#include "shared/scene.hpp"

namespace {

volatile sig_atomic_t g_interrupted = 0;
void on_sigint(int) {
  g_interrupted = 1;
}

namespace fs = std::filesystem;

constexpr double kHostCheckSeconds = 30.0;  // srun may wait a while for a job step to start

/// The run file from the part files; false (and one line naming the part) if a part is missing or
/// unreadable. Never throws: the run's own exit status must still reach the caller.
bool write_run_file(const std::vector<dld::coupler::RunPart>& parts, const std::string& merged) {
  try {
    dld::coupler::merge_run_file(parts, merged);
    return true;
  } catch (const std::exception& e) {
    fmt::print(stderr, "dld-run: run file {} not written: {} (the part files stay)\n", merged,
               e.what());
    return false;
  }
}

/// Whether dld-fluid has welcomed its membranes (its log says so once the handshake is done).
bool handshake_done(const std::string& fluid_log) {
  std::ifstream in(fluid_log);
  std::string line;
  while (std::getline(in, line))
    if (line.find("coupled with ") != std::string::npos) return true;
  return false;
}

/// --dry-run: dld-membrane --check reads the membrane part of the scene (and makes its mesh);
/// its error line and exit code 2 if it refuses it.
int check_membrane_part(const std::string& membrane_exe, const std::string& scene_path,
                        const fs::path& dir) {
  const std::string log = (dir / "membrane-check.log").string();
  dld::coupler::Child c =
      dld::coupler::start_child("dld-membrane", {membrane_exe, scene_path, "--check"}, log);
  if (dld::coupler::wait_child(c) == 0) return 0;
  fmt::print(stderr, "error: {}\n", dld::coupler::error_line(log));
  return 2;
}

struct Options {
  std::string scene_path, membrane = "tracers";
  int tracers = 16;
  std::int64_t steps = 1000;
  bool dry = false, until_certain = false, resume = false;
  bool exchange_every_step = false;  ///< dld-membrane --exchange-every-step
  int pillars = 0;
  int membrane_processes = 0;      ///< 0: the scene's [coupling] membrane_processes
  int threads = 0;                 ///< each program's OpenMP threads; 0: the scene's [run] threads
  std::vector<std::string> hosts;  ///< membrane processes' hosts (placement.hpp)
  std::string fluid_host, start_with;
  int port = 0;  ///< the fluid's tcp port; 0: one from the launcher's process id
  std::int64_t checkpoint_every = 0;
  std::int64_t exact_coupling_for = 0;  ///< first steps at exact coupling (0: the scene's)
  bool exact_coupling = false;          ///< the programs get --exact-coupling (this invocation)
  bool with_cells() const { return membrane == "cells"; }
};

void add_options(CLI::App& app, Options& o) {
  app.add_option("scene", o.scene_path, "scene file (TOML)")->required();
  app.add_option("--membrane", o.membrane,
                 "membrane program: cells (dld-membrane, the scene's [[cells.cell]]) or tracers "
                 "(dld-tracers)")
      ->check(CLI::IsMember({"cells", "tracers"}));
  app.add_option("--tracers", o.tracers, "tracer particles per membrane process")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--steps", o.steps, "steps to run")->check(dld::step_count());
  app.add_option("--pillars", o.pillars,
                 "cells: end the run once every cell has passed this many pillars")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--until-mode-certain", o.until_certain,
               "cells: end the run once every cell's mode (zigzag/displacement) is certain");
  app.add_flag("--exchange-every-step", o.exchange_every_step,
               "membrane processes exchange with the fluid every step while forces are held too "
               "(the same results, slower; for checks)");
  app.add_option("--checkpoint-every", o.checkpoint_every,
                 "cells: steps between checkpoints (one is always written when the run ends)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--resume", o.resume,
               "cells: continue from the newest checkpoint step that holds the fluid and every "
               "cell");
  app.add_option("--membrane-processes", o.membrane_processes,
                 "membrane processes to split the cells among (default: the scene's [coupling] "
                 "membrane_processes); a run resumes with any number of them")
      ->check(CLI::Range(1, 64));
  app.add_option("--threads", o.threads,
                 "OpenMP threads of the fluid and of each membrane process (default: the scene's "
                 "[run] threads; changes the round-off only, so a run resumes with any number)")
      ->check(CLI::Range(1, 1024));
  app.add_option("--exact-coupling-for", o.exact_coupling_for,
                 "cells: run the first STEPS steps (up to the next step a held run resumes "
                 "exactly at) with forces, viscosity field and spreading every step, then the "
                 "scene's [coupling] from the checkpoint they end at; e.g. past the step where the "
                 "held coupling failed (recorded in <run>-exact-coupling.csv)")
      ->check(dld::step_count());
  app.add_flag("--dry-run", o.dry, "validate the scene and print the commands, start nothing");
}

/// Where the membrane processes run (coupler/launcher/placement.hpp).
void add_placement_options(CLI::App& app, Options& o) {
  app.add_option("--hosts", o.hosts,
                 "hosts of the membrane processes, comma-separated (process k on host k mod n; "
                 "over tcp with CURVE; the fluid runs here)")
      ->delimiter(',');
  app.add_option("--start-with", o.start_with,
                 "with --hosts: command that starts a program on {host} (default: srun inside a "
                 "SLURM allocation, else print: print each command to start by hand)");
  app.add_option("--fluid-host", o.fluid_host,
                 "with --hosts: the address the membrane hosts reach this one at (default: its "
                 "host name)");
  app.add_option("--port", o.port, "the fluid's tcp port (default: one from the process id)")
      ->check(CLI::Range(1024, 65535));
}

/// Where a run's files go and how its programs meet.
struct RunPaths {
  fs::path out;       ///< the run file
  fs::path sock_dir;  ///< private folder of the ipc sockets and checks
  fs::path key_dir;   ///< private folder of the CURVE keys: beside the run file with --hosts
  std::string serve, connect;  ///< the fluid's endpoint as it binds and as peers reach it
  std::string stem, scene;     ///< the run's file stem and scene file, as the programs get them
};

/// With --hosts: tcp on every interface, reached at the fluid's host name; paths the other hosts
/// see (a shared file system, as clusters have; the keys in a private folder beside the run).
void place_on_hosts(RunPaths& p, const dld::coupler::Placement& place, int port) {
  p.serve = fmt::format("tcp://*:{}", port);
  p.connect = fmt::format("tcp://{}:{}", place.fluid_address, port);
  p.stem = fs::absolute(p.stem).string();
  p.scene = fs::absolute(p.scene).string();
  p.key_dir = fmt::format("{}-keys-{}", p.stem, getpid());
  fs::create_directories(p.key_dir);
  fs::permissions(p.key_dir, fs::perms::owner_all, fs::perm_options::replace);
}

RunPaths run_paths(const dld::Scene& scene, const std::string& scene_path,
                   const dld::coupler::Placement& place, int port) {
  RunPaths p;
  p.out = fs::path(scene.output.file);
  if (fs::is_directory(p.out)) {  // the run file replaces what is there: never a directory
    throw dld::InputError(
        fmt::format("{}: [output] file '{}' is a directory; expected the path "
                    "of the run file (HDF5)",
                    scene.file, p.out.string()));
  }
  const fs::path run_dir = p.out.has_parent_path() ? p.out.parent_path() : fs::path(".");
  fs::create_directories(run_dir);
  // ipc paths are limited to ~100 bytes: keep the socket in a short private directory.
  p.sock_dir = fs::temp_directory_path() / fmt::format("dld-run-{}", getpid());
  fs::create_directories(p.sock_dir);
  fs::permissions(p.sock_dir, fs::perms::owner_all, fs::perm_options::replace);  // keys, sockets
  // coupling.transport: ipc (default) or tcp over loopback, one port per membrane process from a
  // per-launcher base (tcp across machines: start dld-fluid --serve and dld-membrane --connect by
  // hand, docs/protocol.md).
  if (port == 0) port = 20000 + (getpid() % 2000) * 16;
  const int peers = scene.coupling.membrane_processes;  // one port each: P, P + 1, ...
  if (scene.coupling.transport == "tcp" && port + peers - 1 > 65535)
    throw dld::InputError(
        fmt::format("--port {}: {} membrane processes need ports {} to {}, "
                    "past 65535",
                    port, peers, port, port + peers - 1));
  p.serve = scene.coupling.transport == "tcp" ? fmt::format("tcp://127.0.0.1:{}", port)
                                              : "ipc://" + (p.sock_dir / "fluid").string();
  p.connect = p.serve;
  p.key_dir = p.sock_dir;
  p.stem = (run_dir / p.out.stem()).string();
  p.scene = scene_path;
  if (place.remote()) place_on_hosts(p, place, port);
  return p;
}

/// Cells of the run: [cells] count = N (packed at random by dld-membrane) or one [[cells.cell]]
/// per cell; tracers: --tracers per membrane process.
int cell_count(const dld::Scene& scene, const Options& o) {
  const int peers = scene.coupling.membrane_processes;
  if (!o.with_cells()) return o.tracers * peers;
  const auto* list = scene.document->root().at_path("cells.cell").as_array();
  const auto count = scene.document->root().at_path("cells.count").value<std::int64_t>();
  const int cells = count ? static_cast<int>(*count) : list ? static_cast<int>(list->size()) : 0;
  if (cells < peers) {
    throw dld::InputError(fmt::format(
        "{}: {} cells ([cells] count or [[cells.cell]]) for {} membrane processes ({})",
        o.scene_path, cells, peers,
        o.membrane_processes ? "--membrane-processes" : "[coupling] membrane_processes"));
  }
  return cells;
}

// Checkpoints: <stem>-fluid.ckpt.h5 and <stem>-cells-k.ckpt.h5 (each keeps its previous one as
// .prev); resuming takes the newest step the fluid and a set of them holding every cell have.
std::string fluid_checkpoint(const std::string& stem) {
  return stem + "-fluid.ckpt.h5";
}
std::string cell_checkpoint(const std::string& stem, int k) {
  return fmt::format("{}-cells-{}.ckpt.h5", stem, k);
}

/// With --resume, where the run continues: the fluid's checkpoint and the membrane checkpoints
/// of one step holding every cell, from any earlier number of membrane processes (up to 64, the
/// scene's limit); each new membrane process takes its cells from them.
dld::coupler::ResumePoint resume_point(const Options& o, const std::string& stem, int cells,
                                       int peers) {
  if (!o.resume) return {};
  if (!o.with_cells())
    throw dld::InputError("--resume: only runs with --membrane cells checkpoint");
  constexpr int kMostProcesses = 64;  // the scene's limit: any earlier split is among these
  std::vector<std::string> parts;
  parts.reserve(kMostProcesses);
  for (int k = 0; k < kMostProcesses; ++k) parts.push_back(cell_checkpoint(stem, k));
  return dld::coupler::coupled_resume_point(fluid_checkpoint(stem), parts, cells,
                                            static_cast<std::size_t>(peers));
}

/// Membrane process k's command line (behind what starts it on its host).
std::vector<std::string> membrane_command(const Options& o, const RunPaths& p,
                                          const dld::coupler::Placement& place, int k, int peers,
                                          const dld::coupler::ResumePoint& from) {
  const bool with_cells = o.with_cells();
  std::vector<std::string> c = dld::coupler::start_prefix(place, k);
  c.insert(c.end(), {with_cells ? dld::coupler::find_program("dld-membrane", DLD_MEMBRANE_EXE)
                                : dld::coupler::find_program("dld-tracers", DLD_TRACERS_EXE),
                     p.scene, "--connect", p.connect, "--peer", std::to_string(k), "--peers",
                     std::to_string(peers), "--steps", std::to_string(o.steps), "-o",
                     fmt::format("{}-{}-{}.h5", p.stem, o.membrane, k)});
  if (!with_cells) {
    c.insert(c.end(), {"--count", std::to_string(o.tracers)});
    return c;
  }
  if (o.pillars > 0) c.insert(c.end(), {"--pillars", std::to_string(o.pillars)});
  if (o.until_certain) c.push_back("--until-mode-certain");
  if (o.exchange_every_step) c.push_back("--exchange-every-step");
  if (o.exact_coupling) c.push_back("--exact-coupling");
  if (o.threads > 0) c.insert(c.end(), {"--threads", std::to_string(o.threads)});
  c.insert(c.end(), {"--checkpoint", cell_checkpoint(p.stem, k), "--checkpoint-every",
                     std::to_string(o.checkpoint_every)});
  if (o.resume) {
    c.push_back("--resume");
    c.insert(c.end(), from.cells.begin(), from.cells.end());
  }
  return c;
}

/// The command lines: dld-fluid first, then one per membrane process.
std::vector<std::vector<std::string>> program_commands(const Options& o, const dld::Scene& scene,
                                                       const RunPaths& p,
                                                       const dld::coupler::Placement& place,
                                                       int cells,
                                                       const dld::coupler::ResumePoint& from) {
  const int peers = scene.coupling.membrane_processes;
  std::vector<std::vector<std::string>> commands;
  commands.push_back({dld::coupler::find_program("dld-fluid", DLD_FLUID_EXE), p.scene, "--serve",
                      p.serve, "--peers", std::to_string(peers), "--cells", std::to_string(cells),
                      "-o", p.stem + "-fluid.h5"});
  if (o.threads > 0)
    commands[0].insert(commands[0].end(), {"--threads", std::to_string(o.threads)});
  if (o.with_cells()) {
    commands[0].insert(commands[0].end(),
                       {"--checkpoint", fluid_checkpoint(p.stem), "--checkpoint-every",
                        std::to_string(o.checkpoint_every)});
    if (o.resume) commands[0].insert(commands[0].end(), {"--resume", from.fluid});
    if (o.exact_coupling) commands[0].push_back("--exact-coupling");
  }
  for (int k = 0; k < peers; ++k) commands.push_back(membrane_command(o, p, place, k, peers, from));
  return commands;
}

/// Over tcp the run gets its own CURVE keys (docs/protocol.md, "Security"): a pair for the fluid
/// and one per membrane process, in the run's private folder; the fluid admits those clients only.
void add_curve_keys(std::vector<std::vector<std::string>>& commands, const RunPaths& p) {
  if (p.serve.rfind("tcp://", 0) != 0) return;
  const std::string fluid = (p.key_dir / "fluid").string();
  dld::coupler::write_key_files(fluid, dld::coupler::new_key_pair());
  commands[0].insert(commands[0].end(), {"--curve-key", fluid + ".key", "--curve-clients"});
  for (std::size_t k = 1; k < commands.size(); ++k) {
    const std::string client = (p.key_dir / fmt::format("membrane-{}", k - 1)).string();
    dld::coupler::write_key_files(client, dld::coupler::new_key_pair());
    commands[0].push_back(client + ".pub");
    commands[k].insert(commands[k].end(),
                       {"--curve-key", client + ".key", "--curve-server", fluid + ".pub"});
  }
}

/// Progress every 5 s: the fluid's last line and each membrane program's (pillars, ETA, modes).
void report_progress(const std::vector<dld::coupler::Child>& children, double seconds) {
  fmt::print("[{:.0f} s] fluid: {}\n", seconds, dld::coupler::last_line(children[0].log));
  for (std::size_t k = 1; k < children.size(); ++k)
    fmt::print("      {}: {}\n", children[k].name, dld::coupler::last_line(children[k].log));
  std::fflush(stdout);
}

/// Watches the programs until all have ended; returns the first failure's exit code (0: none).
/// Ctrl-C/SIGTERM goes to the fluid, which ends the run for all at one step; a failed child stops
/// the others through the coupler within the scene's timeout, after which (plus a margin) they
/// are killed.
int supervise(std::vector<dld::coupler::Child>& children, const dld::Scene& scene) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  int failed = 0;
  bool interrupted_sent = false;
  auto last_report = start;
  const auto margin =
      std::chrono::milliseconds(static_cast<long>(scene.coupling.timeout_s * 1000) + 5000);
  std::optional<Clock::time_point> deadline;
  while (true) {
    bool any_running = false;
    for (auto& c : children) {
      if (dld::coupler::poll_child(c) && c.exit_code != 0) {
        fmt::print(stderr, "dld-run: {} stopped with exit code {}: {}\n", c.name, c.exit_code,
                   dld::coupler::error_line(c.log));
        failed = failed ? failed : c.exit_code;
        // A membrane program that fails before the fluid has its hellos would leave the fluid
        // waiting its whole handshake timeout; there is nothing of the run to keep yet.
        if (&c != &children[0] && children[0].running && !handshake_done(children[0].log))
          dld::coupler::signal_child(children[0], SIGTERM);
        // And the other way round: membrane programs without their hello yet (still meshing or
        // packing cells) would not hear of the fluid's failure until the timeout.
        if (&c == &children[0] && !handshake_done(c.log))
          for (auto& m : children)
            if (&m != &c && m.running) dld::coupler::signal_child(m, SIGTERM);
      }
      any_running = any_running || c.running;
    }
    if (!any_running) return failed;
    if (g_interrupted && !interrupted_sent) {
      fmt::print(stderr,
                 "dld-run: interrupted; asking the fluid to end the run at the next step a resume "
                 "repeats exactly (a multiple of {})\n",
                 scene.coupling.exact_resume_every());
      dld::coupler::signal_child(children[0], SIGINT);
      interrupted_sent = true;
    }
    const auto now = Clock::now();
    if (failed && now - start > std::chrono::seconds(1)) {
      if (!deadline) deadline = now + margin;
      if (now > *deadline)
        for (auto& c : children) dld::coupler::signal_child(c, SIGKILL);
    }
    if (now - last_report > std::chrono::seconds(5)) {
      report_progress(children, std::chrono::duration<double>(now - start).count());
      last_report = now;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

/// Starts dld-fluid and the membrane programs, each logging to <stem>-<name>.log; with
/// --start-with print, the membrane programs' commands are printed for the user to start.
std::vector<dld::coupler::Child> start_programs(const std::vector<std::vector<std::string>>& cmds,
                                                const Options& o, const std::string& stem,
                                                const dld::coupler::Placement& place) {
  std::vector<dld::coupler::Child> children;
  // Should dld-run die without stopping them (SIGKILL), the fluid gets what Ctrl-C sends it
  // and ends the run for every program at one step, with checkpoints.
  children.push_back(dld::coupler::start_child("dld-fluid", cmds[0], stem + "-fluid.log", SIGINT));
  if (place.printed()) {
    fmt::print(
        "dld-run: start each membrane process on its host within 60 s (the fluid's "
        "handshake timeout), from a folder that sees these paths:\n");
    for (std::size_t k = 1; k < cmds.size(); ++k)
      fmt::print("  on {}:  {}\n", place.hosts[k - 1], fmt::join(cmds[k], " "));
    std::fflush(stdout);
    return children;
  }
  for (std::size_t k = 1; k < cmds.size(); ++k)
    children.push_back(
        dld::coupler::start_child(fmt::format("{}-{}", o.membrane, k - 1), cmds[k],
                                  fmt::format("{}-{}-{}.log", stem, o.membrane, k - 1)));
  return children;
}

/// Removes a folder however run_main is left (--dry-run, an error, the end of the run).
struct RemoveOnExit {
  explicit RemoveOnExit(fs::path p) : path(std::move(p)) {}
  fs::path path;
  RemoveOnExit(const RemoveOnExit&) = delete;
  RemoveOnExit& operator=(const RemoveOnExit&) = delete;
  ~RemoveOnExit() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
};

/// One start of the programs from `from` until they end: their commands (and --dry-run's check),
/// their supervision and the run file; the first failure's exit code, 130 when interrupted.
int run_programs(const Options& o, const dld::Scene& scene, const RunPaths& paths,
                 const dld::coupler::Placement& place, int cells,
                 const dld::coupler::ResumePoint& from) {
  if (o.resume) fmt::print("dld-run: resuming at step {}\n", from.step);
  if (o.resume && from.step % scene.coupling.exact_resume_every() != 0)
    fmt::print(stderr,
               "dld-run: warning: step {} is not a multiple of {} ([coupling] force_every, "
               "viscosity_field_every): the held forces and viscosity field are recomputed "
               "there, so the run differs slightly from one that went straight through\n",
               from.step, scene.coupling.exact_resume_every());
  auto commands = program_commands(o, scene, paths, place, cells, from);
  add_curve_keys(commands, paths);
  for (const auto& c : commands) fmt::print("  {}\n", fmt::join(c, " "));
  if (o.dry) {  // the membrane part too: dld-run itself reads only the fluid's tables
    if (!o.with_cells()) return 0;
    return check_membrane_part(dld::coupler::find_program("dld-membrane", DLD_MEMBRANE_EXE),
                               o.scene_path, paths.sock_dir);
  }
  dld::coupler::check_hosts(place, paths.sock_dir.string(), kHostCheckSeconds);
  // The run file describes this run or does not exist: one left by an earlier run of the scene
  // would otherwise stand for this one if this one's parts cannot be merged.
  const std::string merged = paths.out.string();
  std::error_code ignored;  // none there, or one this run cannot remove: merging will say so
  fs::remove(merged, ignored);
  signal(SIGINT, on_sigint);
  signal(SIGTERM, on_sigint);  // SLURM's way to end a job: the same clean stop as Ctrl-C
  const auto start = std::chrono::steady_clock::now();
  std::vector<dld::coupler::Child> children = start_programs(commands, o, paths.stem, place);
  const int failed = supervise(children, scene);
  // After a failure too: what the programs wrote up to it is what there is to look at.
  const bool have_run_file = write_run_file(
      dld::coupler::run_parts(paths.stem, o.membrane, scene.coupling.membrane_processes), merged);
  if (failed) {
    if (have_run_file)
      fmt::print(stderr, "dld-run: run file {} holds what the programs wrote before the failure\n",
                 merged);
    return failed;
  }
  fmt::print("dld-run: done in {:.1f} s; run file {}, parts {}-*.h5, logs {}-*.log\n",
             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
             have_run_file ? merged : "not written", paths.stem, paths.stem);
  return g_interrupted ? 130 : 0;
}

/// --exact-coupling-for N: the step the exact start is to end at, N steps after `from` rounded up
/// to the next step a held run resumes exactly at (a start that ends sooner, at --steps or
/// interrupted, leaves the rest to the next resume); 0 when there is nothing to do (no N, or a
/// scene that holds nothing).
std::int64_t exact_coupling_until(const Options& o, const dld::Scene& scene, std::int64_t from) {
  if (o.exact_coupling_for == 0) return 0;
  if (!o.with_cells())
    throw dld::InputError(
        "--exact-coupling-for: only runs with --membrane cells (the held coupling resumes from "
        "the checkpoint the exact steps end at)");
  if (!scene.coupling.holds()) {
    fmt::print(
        "dld-run: --exact-coupling-for: {} holds nothing ([coupling] force_every and "
        "viscosity_field_every are 1): the whole run is exact\n",
        o.scene_path);
    return 0;
  }
  const std::int64_t every = scene.coupling.exact_resume_every();
  return (from + o.exact_coupling_for + every - 1) / every * every;  // both at most 1e15
}

/// The exact steps and where they were to end: from --exact-coupling-for, or what is left of a
/// stretch an earlier start ended early (interrupted, or stopped after a checkpoint).
std::int64_t exact_end(const Options& o, const dld::Scene& scene, const std::string& record,
                       std::int64_t from) {
  const std::int64_t asked = exact_coupling_until(o, scene, from);
  if (!o.resume || !scene.coupling.holds()) return asked;
  const std::int64_t left =
      dld::coupler::pending_exact_end(dld::coupler::read_exact_stretches(record), from);
  if (left > asked)
    fmt::print("dld-run: the exact stretch begun earlier was to end at step {}: it goes on\n",
               left);
  return std::max(asked, left);
}

/// The exact start (when there is one), then the scene's coupling from the checkpoint it ended
/// at. The exact steps are recorded in <stem>-exact-coupling.csv however they end, as far as
/// their checkpoints reach, with where they were to end.
int run_phases(Options o, const dld::Scene& scene, const RunPaths& paths,
               const dld::coupler::Placement& place, int cells) {
  const int peers = scene.coupling.membrane_processes;
  const std::string record = dld::coupler::exact_stretches_file(paths.stem);
  auto from = resume_point(o, paths.stem, cells, peers);
  const std::int64_t until = exact_end(o, scene, record, from.step);
  if (until <= from.step) return run_programs(o, scene, paths, place, cells, from);
  fmt::print(
      "dld-run: steps {} to {} at exact coupling (--exact-coupling-for), then the scene's "
      "[coupling] from the checkpoint at step {}\n",
      from.step, until, until);
  Options exact = o;
  exact.exact_coupling = true;
  exact.steps = std::min(o.steps, until);
  dld::Scene exact_scene = scene;
  exact_scene.coupling.make_exact();
  const int rc = run_programs(exact, exact_scene, paths, place, cells, from);
  if (o.dry) return rc;
  o.resume = true;
  dld::coupler::ResumePoint after;
  try {
    after = resume_point(o, paths.stem, cells, peers);
  } catch (const dld::InputError&) {  // no checkpoint of every program: nothing to record
    return rc;
  }
  if (after.step > from.step)
    dld::coupler::append_exact_stretch(record, {from.step, after.step, until});
  // Failed, interrupted, or ended before `until` by its stop rule: that is where the run stands.
  if (rc != 0 || after.step < until || after.step >= o.steps) return rc;
  return run_programs(o, scene, paths, place, cells, after);
}

}  // namespace

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-run: one coupled run of a scene (fluid + membrane programs over ipc or tcp)"};
  Options o;
  add_options(app, o);
  add_placement_options(app, o);
  CLI11_PARSE(app, argc, argv);
  try {
    dld::Scene scene = dld::load_scene(o.scene_path);
    // Only dld-run reads the number (the programs get --peers): the scene file, and with it the
    // hash every checkpoint is checked against, stays as it is.
    if (o.membrane_processes) scene.coupling.membrane_processes = o.membrane_processes;
    fmt::print("{}\n", scene.describe());
    // The fluid and membrane programs take turns on the same cores: OpenMP threads that spin after
    // a parallel region (libgomp's default) steal the core the other program needs next. Sleeping
    // instead made 17 cells 1.2-1.5x and 3 cells 1.8x faster per coupled step (one cell 10-20 %
    // slower; docs/performance.md, "Coupled step"). A policy the user set is kept.
    setenv("OMP_WAIT_POLICY", "PASSIVE", /*overwrite=*/0);
    // But a thread that sleeps at once between the many parallel regions of one program's step
    // waits for a wake-up each time (slow in a virtual machine): a short spin first made one run
    // on two threads 1.3-1.6x faster at `fast` and 1.2x at the exact coupling, while the other
    // program's turn is long enough to put them to sleep (docs/performance.md, "A short spin
    // before sleeping"). GCC's OpenMP reads GOMP_SPINCOUNT; other runtimes ignore it.
    setenv("GOMP_SPINCOUNT", "20000", /*overwrite=*/0);
    const auto place = dld::coupler::make_placement(o.hosts, scene.coupling.membrane_processes,
                                                    o.fluid_host, o.start_with);
    if (place.remote()) scene.coupling.transport = "tcp";  // with CURVE (add_curve_keys)
    if (!place.warning.empty()) fmt::print(stderr, "dld-run: warning: {}\n", place.warning);
    const RunPaths paths = run_paths(scene, o.scene_path, place, o.port);
    const RemoveOnExit sockets{paths.sock_dir}, keys{paths.key_dir};
    return run_phases(o, scene, paths, place, cell_count(scene, o));
  } catch (const dld::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-run", run_main, argc, argv);
}
