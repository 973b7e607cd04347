// SPDX-License-Identifier: MIT
// Child processes of the launcher: start with output to a log file, poll, signal.
#pragma once
#include <sys/types.h>

#include <string>
#include <vector>

namespace dld::coupler {

struct Child {
  std::string name;  ///< "dld-fluid", "dld-tracers-0", ...
  std::string log;   ///< file receiving its stdout and stderr
  pid_t pid = -1;
  bool running = false;
  int exit_code = 0;  ///< valid once !running; 128 + signal if killed
};

/// Starts argv[0] with the given arguments; stdout and stderr go to child.log (and, when `echo`
/// is true, to the launcher's terminal as well through `tee`-like forwarding by the caller).
/// With `parent_death_signal` (e.g. SIGINT) the child gets that signal when the launcher dies,
/// however it dies (SIGKILL included), so that it never runs on unattended.
Child start_child(const std::string& name, const std::vector<std::string>& argv,
                  const std::string& log, int parent_death_signal = 0);
/// Updates running/exit_code without blocking; true if the child ended in this call.
bool poll_child(Child& c);
void signal_child(const Child& c, int sig);
/// Blocks until the child ends; returns its exit code (128 + signal if killed).
int wait_child(Child& c);

/// A sibling program: next to the running executable (install tree), else at `build_path`.
std::string find_program(const std::string& name, const std::string& build_path);
/// The last non-empty line of a text file ("" if it cannot be read): a child's latest progress.
std::string last_line(const std::string& path);
/// The line that says why a program failed: its last error line ("[program] error: ..." as
/// shared/log writes them, or "program: error: ..." from a program's top level), else its last
/// line.
std::string error_line(const std::string& path);

}  // namespace dld::coupler
