// SPDX-License-Identifier: MIT
#include "coupler/launcher/process.hpp"

#include <errno.h>
#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "shared/input_error.hpp"

namespace dld::coupler {

Child start_child(const std::string& name, const std::vector<std::string>& argv,
                  const std::string& log, int parent_death_signal) {
  Child c{name, log};
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    throw InputError(fmt::format("{}: cannot create log file", log));
  }
  const pid_t parent = getpid();
  c.pid = fork();
  if (c.pid < 0) {
    throw std::runtime_error("fork failed");
  }
  if (c.pid == 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    ::close(fd);
    setpgid(0, 0);  // Ctrl-C reaches the launcher only; it decides how the children stop
    if (parent_death_signal != 0) {
      prctl(PR_SET_PDEATHSIG, parent_death_signal);
      if (getppid() != parent) raise(parent_death_signal);  // the launcher died before prctl
    }
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (const auto& a : argv) {
      args.push_back(const_cast<char*>(a.c_str()));
    }
    args.push_back(nullptr);
    execvp(args[0], args.data());  // a bare name (srun, ssh) is looked up in PATH
    fmt::print(stderr, "cannot start {}\n", argv[0]);
    _exit(127);
  }
  ::close(fd);
  c.running = true;
  return c;
}

bool poll_child(Child& c) {
  if (!c.running) {
    return false;
  }
  int status = 0;
  if (waitpid(c.pid, &status, WNOHANG) != c.pid) {
    return false;
  }
  c.running = false;
  c.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return true;
}

void signal_child(const Child& c, int sig) {
  if (c.running) {
    kill(c.pid, sig);
  }
}

int wait_child(Child& c) {
  if (!c.running) {
    return c.exit_code;
  }
  int status = 0;
  while (waitpid(c.pid, &status, 0) < 0 && errno == EINTR) {
  }
  c.running = false;
  c.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return c.exit_code;
}

std::string find_program(const std::string& name, const std::string& build_path) {
  namespace fs = std::filesystem;
  const fs::path self = fs::read_symlink("/proc/self/exe").parent_path();
  for (const fs::path& p : {self / name, fs::path(build_path)}) {
    if (fs::exists(p)) {
      return p.string();
    }
  }
  throw InputError(fmt::format("cannot find the program {} (looked next to {} and at {})", name,
                               self.string(), build_path));
}

std::string last_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line)) {
    if (!line.empty()) {
      last = line;
    }
  }
  return last;
}

std::string error_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, error;
  while (std::getline(in, line)) {
    if (line.find("] error: ") != std::string::npos ||
        line.find(": error: ") != std::string::npos || line.rfind("error: ", 0) == 0)
      error = line;
  }
  return error.empty() ? last_line(path) : error;
}

}  // namespace dld::coupler
