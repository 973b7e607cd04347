// SPDX-License-Identifier: MIT
#include "coupler/launcher/placement.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "coupler/launcher/process.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {
namespace {

std::string this_host_name() {
  std::array<char, 256> name{};
  if (gethostname(name.data(), name.size() - 1) != 0) return "localhost";
  return name.data();
}

std::vector<std::string> words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

/// Ends `c` within `timeout_s` (killed after it); its exit code.
int wait_with_timeout(Child& c, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
  while (!poll_child(c) && c.running) {
    if (std::chrono::steady_clock::now() > deadline) {
      signal_child(c, SIGKILL);
      wait_child(c);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return c.exit_code;
}

}  // namespace

bool is_this_host(const std::string& host) {
  return host == "localhost" || host == "127.0.0.1" || host == this_host_name();
}

Placement make_placement(const std::vector<std::string>& hosts, int processes,
                         const std::string& fluid_address, const std::string& start_with) {
  Placement p;
  if (hosts.empty()) {
    if (!start_with.empty() || !fluid_address.empty())
      throw InputError(
          "--start-with and --fluid-host place membrane processes on --hosts: "
          "expected --hosts too");
    return p;
  }
  if (static_cast<int>(hosts.size()) > processes)
    throw InputError(
        fmt::format("--hosts: {} hosts for {} membrane processes (expected at most "
                    "one host per process; see --membrane-processes)",
                    hosts.size(), processes));
  for (std::size_t i = 0; i < hosts.size(); ++i)
    if (hosts[i].empty() || hosts[i].find_first_of(" \t/,") != std::string::npos)
      throw InputError(fmt::format("--hosts: entry {} '{}': expected a host name", i, hosts[i]));
  for (int k = 0; k < processes; ++k) p.hosts.push_back(hosts[k % hosts.size()]);
  p.fluid_address = fluid_address.empty() ? this_host_name() : fluid_address;
  p.start_with = start_with;
  const bool in_slurm = std::getenv("SLURM_JOB_ID") != nullptr;
  if (p.start_with.empty()) p.start_with = in_slurm ? kSrunTemplate : "print";
  // slurmd sets SLURMD_NODENAME on the allocation's nodes only: an salloc shell lacks it.
  if (in_slurm && std::getenv("SLURMD_NODENAME") == nullptr)
    p.warning = fmt::format(
        "inside a SLURM allocation but not on one of its nodes (an salloc shell?): the fluid runs "
        "here, on {}; submit with sbatch to run it on the allocation's first node",
        this_host_name());
  if (!p.printed() && p.start_with.find("{host}") == std::string::npos)
    throw InputError(
        fmt::format("--start-with '{}': expected a command with {{host}} in it "
                    "(e.g. \"ssh {{host}}\"), or print",
                    p.start_with));
  return p;
}

std::vector<std::string> start_prefix(const Placement& p, int k) {
  if (!p.remote() || p.printed()) return {};
  const std::string& host = p.hosts[static_cast<std::size_t>(k)];
  if (is_this_host(host)) return {};
  std::vector<std::string> w = words(p.start_with);
  for (std::string& s : w)
    for (std::size_t at; (at = s.find("{host}")) != std::string::npos;) s.replace(at, 6, host);
  return w;
}

void check_hosts(const Placement& p, const std::string& log_dir, double timeout_s) {
  if (!p.remote() || p.printed()) return;
  std::vector<std::string> checked;
  for (std::size_t k = 0; k < p.hosts.size(); ++k) {
    const std::string& host = p.hosts[k];
    if (is_this_host(host) || std::find(checked.begin(), checked.end(), host) != checked.end())
      continue;
    checked.push_back(host);
    std::vector<std::string> cmd = start_prefix(p, static_cast<int>(k));
    cmd.emplace_back("true");
    const std::string log = (std::filesystem::path(log_dir) / ("check-" + host + ".log")).string();
    Child c = start_child("check " + host, cmd, log);
    const int code = wait_with_timeout(c, timeout_s);
    if (code != 0)
      throw InputError(fmt::format(
          "--hosts: host '{}' (membrane process {}) cannot be reached through '{}': {}", host, k,
          p.start_with,
          code < 0 ? fmt::format("no answer in {:.0f} s", timeout_s) : error_line(log)));
  }
}

}  // namespace dld::coupler
