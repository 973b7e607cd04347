// SPDX-License-Identifier: MIT
// Where dld-run's membrane processes run (issue 14): on this machine, or spread over a hosts list
// (dld-run --hosts), each started there through a command template (--start-with, e.g.
// "srun --nodelist={host} ..." inside a SLURM allocation, "ssh {host}") or printed for the user to
// start by hand. The fluid always runs where dld-run does; membrane hosts reach it over tcp.
// Placement is not part of the scene (nor of its hash), so a run resumes on other hosts.
#pragma once
#include <string>
#include <vector>

namespace dld::coupler {

struct Placement {
  std::vector<std::string> hosts;  ///< host of membrane process k (K entries); empty: all here
  std::string fluid_address;       ///< the address the membrane hosts connect to
  /// Command template, "{host}" replaced; "print": print each command for the user to start.
  std::string start_with;
  std::string warning;  ///< to print before the run, e.g. an salloc shell on the login node
  bool remote() const { return !hosts.empty(); }
  bool printed() const { return start_with == "print"; }
};

/// The srun template used inside a SLURM allocation (SLURM_JOB_ID set) when --start-with is not
/// given: one task on the named node, the whole step ended if it fails.
inline constexpr const char* kSrunTemplate =
    "srun --nodes=1 --ntasks=1 --nodelist={host} --kill-on-bad-exit=1 --quiet";

/// Placement of `processes` membrane processes over `hosts` (round robin: process k on
/// hosts[k % n]; more hosts than processes is an error). `fluid_address` "" is this machine's
/// host name; `start_with` "" is kSrunTemplate inside SLURM, else "print". Throws InputError
/// naming --hosts, --start-with or --fluid-host.
Placement make_placement(const std::vector<std::string>& hosts, int processes,
                         const std::string& fluid_address, const std::string& start_with);

/// Whether `host` is this machine ("localhost", "127.0.0.1" or its host name): started directly.
bool is_this_host(const std::string& host);

/// The words that start a program on membrane process k's host (empty: start it directly).
std::vector<std::string> start_prefix(const Placement& p, int k);

/// Starts `true` on each distinct remote host through the template (at most `timeout_s` each):
/// an unreachable host is an InputError naming it, its first membrane process and the template's
/// error line. Logs go to `log_dir`. Nothing to do when printed or all hosts are this one.
void check_hosts(const Placement& p, const std::string& log_dir, double timeout_s);

}  // namespace dld::coupler
