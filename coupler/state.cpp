// SPDX-License-Identifier: MIT
#include "coupler/state.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace dld::coupler {

std::string_view to_string(State state) {
  switch (state) {
    case State::created:
      return "created";
    case State::running:
      return "running";
    case State::have_step:
      return "have_step";
    case State::ended:
      return "ended";
    case State::failed:
      return "failed";
    case State::finalized:
      return "finalized";
  }
  return "unknown";
}

void check_call(std::string_view self, std::string_view call, State state,
                std::initializer_list<State> allowed) {
  if (std::find(allowed.begin(), allowed.end(), state) != allowed.end()) {
    return;
  }
  std::string_view why;
  switch (state) {
    case State::created:
      why = "before initialize()";
      break;
    case State::running:
      why = "while the step is not received yet (call receive() first)";
      break;
    case State::have_step:
      why = "while a received step awaits send_velocities()";
      break;
    case State::ended:
      why = "after the peer ended the run";
      break;
    case State::failed:
      why = "after a coupling error";
      break;
    case State::finalized:
      why = "after finalize()";
      break;
  }
  if (state == State::running && call == "initialize()") {
    why = "twice";
  }
  throw std::logic_error(fmt::format("{}: {} called {}", self, call, why));
}

}  // namespace dld::coupler
