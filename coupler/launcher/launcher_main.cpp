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
#include <thread>

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

/// Step of a checkpoint file, or -1 if it is missing or unreadable.
std::int64_t checkpoint_step(const std::string& path, const std::string& group) {
  if (!fs::exists(path)) {
    return -1;
  }
  try {
    return static_cast<std::int64_t>(
        dld::H5File(path, dld::H5File::Mode::kRead).read_attribute_number(group, "step"));
  } catch (const dld::InputError&) {
    return -1;
  }
}

/// For each (file, group), the file (itself or its .prev) at the newest step all of them have.
std::vector<std::string> common_checkpoint(
    const std::vector<std::pair<std::string, std::string>>& sides) {
  std::vector<std::int64_t> candidates;
  for (const auto& [path, group] : sides) {
    for (const std::string& p : {path, path + ".prev"}) {
      candidates.push_back(checkpoint_step(p, group));
    }
  }
  std::sort(candidates.rbegin(), candidates.rend());
  for (const std::int64_t step : candidates) {
    if (step < 0) {
      break;
    }
    std::vector<std::string> chosen;
    for (const auto& [path, group] : sides) {
      for (const std::string& p : {path, path + ".prev"}) {
        if (checkpoint_step(p, group) == step) {
          chosen.push_back(p);
          break;
        }
      }
    }
    if (chosen.size() == sides.size()) {
      return chosen;
    }
  }
  // Each file and why it cannot be used: a corrupt file is not a missing one.
  std::string found;
  for (const auto& [path, group] : sides) {
    const std::int64_t step = checkpoint_step(path, group);
    found += fmt::format(" {} ({})", path,
                         step >= 0           ? fmt::format("step {}", step)
                         : !fs::exists(path) ? std::string("no such file")
                                             : std::string("not a readable checkpoint"));
  }
  throw dld::InputError("--resume: no checkpoint step shared by every program:" + found);
}

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

}  // namespace

static int run_main(int argc, char** argv) {
  CLI::App app{"dld-run: one coupled run of a scene (fluid + membrane programs over ipc or tcp)"};
  std::string scene_path, membrane = "tracers";
  int tracers = 16;
  std::int64_t steps = 1000;
  bool dry = false, until_certain = false;
  int pillars = 0;
  std::int64_t checkpoint_every = 0;
  bool resume = false;
  app.add_option("scene", scene_path, "scene file (TOML)")->required();
  app.add_option("--membrane", membrane,
                 "membrane program: cells (dld-membrane, the scene's [[cells.cell]]) or tracers "
                 "(dld-tracers)")
      ->check(CLI::IsMember({"cells", "tracers"}));
  app.add_option("--tracers", tracers, "tracer particles per membrane process")
      ->check(CLI::Range(1, 1000000));
  app.add_option("--steps", steps, "steps to run")->check(dld::step_count());
  app.add_option("--pillars", pillars,
                 "cells: end the run once every cell has passed this many pillars")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--until-mode-certain", until_certain,
               "cells: end the run once every cell's mode (zigzag/displacement) is certain");
  app.add_option("--checkpoint-every", checkpoint_every,
                 "cells: steps between checkpoints (one is always written when the run ends)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--resume", resume,
               "cells: continue from the newest checkpoint step that every program has");
  app.add_flag("--dry-run", dry, "validate the scene and print the commands, start nothing");
  CLI11_PARSE(app, argc, argv);

  try {
    const dld::Scene scene = dld::load_scene(scene_path);
    fmt::print("{}\n", scene.describe());
    // The fluid and membrane programs take turns on the same cores: OpenMP threads that spin after
    // a parallel region (libgomp's default) steal the core the other program needs next. Sleeping
    // instead made 17 cells 1.2-1.5x and 3 cells 1.8x faster per coupled step (one cell 10-20 %
    // slower; docs/performance.md, "Coupled step"). A policy the user set is kept.
    setenv("OMP_WAIT_POLICY", "PASSIVE", /*overwrite=*/0);
    const int peers = scene.coupling.membrane_processes;
    const fs::path out = fs::path(scene.output.file);
    if (fs::is_directory(out)) {  // the run file replaces what is there: never a directory
      throw dld::InputError(
          fmt::format("{}: [output] file '{}' is a directory; expected the path "
                      "of the run file (HDF5)",
                      scene.file, out.string()));
    }
    const fs::path run_dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
    fs::create_directories(run_dir);
    // ipc paths are limited to ~100 bytes: keep the socket in a short private directory.
    const fs::path sock_dir = fs::temp_directory_path() / fmt::format("dld-run-{}", getpid());
    fs::create_directories(sock_dir);
    // Gone however this function is left (--dry-run, an error, the end of the run).
    const struct RemoveOnExit {
      fs::path path;
      ~RemoveOnExit() {
        std::error_code ignored;
        fs::remove_all(path, ignored);
      }
    } sock_dir_guard{sock_dir};
    // coupling.transport: ipc (default) or tcp over loopback, one port per membrane process from a
    // per-launcher base (tcp across machines: start dld-fluid --serve and dld-membrane --connect by
    // hand, docs/protocol.md).
    const std::string endpoint =
        scene.coupling.transport == "tcp"
            ? fmt::format("tcp://127.0.0.1:{}", 20000 + (getpid() % 2000) * 16)
            : "ipc://" + (sock_dir / "fluid").string();
    const std::string stem = (run_dir / out.stem()).string();

    const bool with_cells = membrane == "cells";
    int cells = tracers * peers;
    if (with_cells) {
      // [cells] count = N (packed at random by dld-membrane) or one [[cells.cell]] per cell.
      const auto* list = scene.document->root().at_path("cells.cell").as_array();
      const auto count = scene.document->root().at_path("cells.count").value<std::int64_t>();
      cells = count ? static_cast<int>(*count) : list ? static_cast<int>(list->size()) : 0;
      if (cells < peers) {
        throw dld::InputError(
            fmt::format("{}: {} cells ([cells] count or [[cells.cell]]) for {} "
                        "membrane processes",
                        scene_path, cells, peers));
      }
    }
    // Checkpoints: <stem>-fluid.ckpt.h5 and <stem>-cells-k.ckpt.h5 (each keeps its previous one as
    // .prev); resuming takes the newest step every program has.
    const std::string fluid_ckpt = stem + "-fluid.ckpt.h5";
    auto cell_ckpt = [&](int k) { return fmt::format("{}-cells-{}.ckpt.h5", stem, k); };
    std::vector<std::string> resume_from(static_cast<std::size_t>(peers) + 1);
    if (resume) {
      if (!with_cells) {
        throw dld::InputError("--resume: only runs with --membrane cells checkpoint");
      }
      std::vector<std::pair<std::string, std::string>> sides{{fluid_ckpt, "/fluid"}};
      for (int k = 0; k < peers; ++k) {
        sides.emplace_back(cell_ckpt(k), "/membrane");
      }
      const auto chosen = common_checkpoint(sides);
      for (std::size_t i = 0; i < chosen.size(); ++i) {
        resume_from[i] = chosen[i];
      }
    }
    std::vector<std::vector<std::string>> commands;
    commands.push_back({dld::coupler::find_program("dld-fluid", DLD_FLUID_EXE), scene_path,
                        "--serve", endpoint, "--peers", std::to_string(peers), "--cells",
                        std::to_string(cells), "-o", stem + "-fluid.h5"});
    if (with_cells) {
      commands[0].insert(commands[0].end(), {"--checkpoint", fluid_ckpt, "--checkpoint-every",
                                             std::to_string(checkpoint_every)});
      if (resume) {
        commands[0].insert(commands[0].end(), {"--resume", resume_from[0]});
      }
    }
    for (int k = 0; k < peers; ++k) {
      std::vector<std::string> c{with_cells
                                     ? dld::coupler::find_program("dld-membrane", DLD_MEMBRANE_EXE)
                                     : dld::coupler::find_program("dld-tracers", DLD_TRACERS_EXE),
                                 scene_path,
                                 "--connect",
                                 endpoint,
                                 "--peer",
                                 std::to_string(k),
                                 "--peers",
                                 std::to_string(peers),
                                 "--steps",
                                 std::to_string(steps),
                                 "-o",
                                 fmt::format("{}-{}-{}.h5", stem, membrane, k)};
      if (!with_cells) {
        c.insert(c.end(), {"--count", std::to_string(tracers)});
      }
      if (with_cells && pillars > 0) {
        c.insert(c.end(), {"--pillars", std::to_string(pillars)});
      }
      if (with_cells && until_certain) {
        c.push_back("--until-mode-certain");
      }
      if (with_cells) {
        c.insert(c.end(), {"--checkpoint", cell_ckpt(k), "--checkpoint-every",
                           std::to_string(checkpoint_every)});
        if (resume) {
          c.insert(c.end(), {"--resume", resume_from[static_cast<std::size_t>(k) + 1]});
        }
      }
      commands.push_back(c);
    }
    for (const auto& c : commands) {
      fmt::print("  {}\n", fmt::join(c, " "));
    }
    if (dry) {  // the membrane part too: dld-run itself reads only the fluid's tables
      return with_cells ? check_membrane_part(commands[1][0], scene_path, sock_dir) : 0;
    }

    // The run file describes this run or does not exist: one left by an earlier run of the scene
    // would otherwise stand for this one if this one's parts cannot be merged.
    const std::string merged = out.string();
    std::error_code ignored;  // none there, or one this run cannot remove: merging will say so
    fs::remove(merged, ignored);
    signal(SIGINT, on_sigint);
    signal(SIGTERM, on_sigint);  // SLURM's way to end a job: the same clean stop as Ctrl-C
    std::vector<dld::coupler::Child> children;
    // Should dld-run die without stopping them (SIGKILL), the fluid gets what Ctrl-C sends it
    // and ends the run for every program at one step, with checkpoints.
    children.push_back(
        dld::coupler::start_child("dld-fluid", commands[0], stem + "-fluid.log", SIGINT));
    for (int k = 0; k < peers; ++k) {
      children.push_back(dld::coupler::start_child(fmt::format("{}-{}", membrane, k),
                                                   commands[k + 1],
                                                   fmt::format("{}-{}-{}.log", stem, membrane, k)));
    }
    const auto start = std::chrono::steady_clock::now();
    int failed = 0;
    bool interrupted_sent = false;
    auto last_report = start;
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
        }
        any_running = any_running || c.running;
      }
      if (!any_running) {
        break;
      }
      if (g_interrupted && !interrupted_sent) {
        fmt::print(stderr,
                   "dld-run: interrupted; asking the fluid to end the run after this step\n");
        dld::coupler::signal_child(children[0], SIGINT);
        interrupted_sent = true;
      }
      const auto now = std::chrono::steady_clock::now();
      // A failed child stops the others through the coupler within the scene's timeout; after
      // that (plus a margin) the launcher ends them itself.
      if (failed && now - start > std::chrono::seconds(1)) {
        static auto deadline = now + std::chrono::milliseconds(
                                         static_cast<long>(scene.coupling.timeout_s * 1000) + 5000);
        if (now > deadline) {
          for (auto& c : children) {
            dld::coupler::signal_child(c, SIGKILL);
          }
        }
      }
      if (now - last_report > std::chrono::seconds(5)) {
        fmt::print("[{:.0f} s] fluid: {}\n", std::chrono::duration<double>(now - start).count(),
                   dld::coupler::last_line(children[0].log));
        // The membranes know the cells: pillars passed, ETA and modes.
        for (std::size_t k = 1; k < children.size(); ++k) {
          fmt::print("      {}: {}\n", children[k].name, dld::coupler::last_line(children[k].log));
        }
        std::fflush(stdout);
        last_report = now;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    // After a failure too: what the programs wrote up to it is what there is to look at.
    const bool have_run_file =
        write_run_file(dld::coupler::run_parts(stem, membrane, peers), merged);
    if (failed) {
      if (have_run_file) {
        fmt::print(stderr,
                   "dld-run: run file {} holds what the programs wrote before the failure\n",
                   merged);
      }
      return failed;
    }
    fmt::print("dld-run: done in {:.1f} s; run file {}, parts {}-*.h5, logs {}-*.log\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
               have_run_file ? merged : "not written", stem, stem);
    return g_interrupted ? 130 : 0;
  } catch (const dld::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return 2;
  }
}

int main(int argc, char** argv) {
  return dld::guarded_main("dld-run", run_main, argc, argv);
}
