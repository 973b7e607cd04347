// SPDX-License-Identifier: MIT
#include "analysis/locate.hpp"

#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>

extern char** environ;  // NOLINT: POSIX, passed on to the child

namespace dld::analysis {

std::string locate_source_file(const std::string& relative, const std::string& source_dir) {
  namespace fs = std::filesystem;
  std::vector<fs::path> roots;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    for (fs::path p = exe.parent_path(); roots.size() < 3 && !p.empty(); p = p.parent_path()) {
      roots.push_back(p);
      if (p == p.root_path()) {
        break;
      }
    }
  }
  if (!source_dir.empty()) {
    roots.emplace_back(source_dir);
  }
  for (const auto& r : roots) {
    if (fs::is_regular_file(r / relative, ec)) {
      return (r / relative).string();
    }
  }
  return {};
}

int run_program(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const auto& a : argv) {
    args.push_back(const_cast<char*>(a.c_str()));
  }
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) {
    return 127;
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) {
    return 127;
  }
  if (WIFEXITED(status)) {
    return WEXITSTATUS(status);
  }
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 127;
}

}  // namespace dld::analysis
