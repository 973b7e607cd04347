// SPDX-License-Identifier: MIT
// The lock-step state machine both sides share (docs/protocol.md, "Call order").
//
//   created --initialize()--> running --receive()/advance()--> ... --finalize()--> finalized
//                                |  fluid: running --receive()--> have_step --send_velocities()-->
//                                running
//                                +-- peer sent shutdown --> ended --finalize()--> finalized
//   any error (thrown CouplerError, abort()) --> failed --finalize()--> finalized
//
// A call out of order is a programming error of the caller: std::logic_error, never UB.
#pragma once
#include <initializer_list>
#include <string_view>

namespace dld::coupler {

enum class State { created, running, have_step, ended, failed, finalized };

std::string_view to_string(State state);

/// Throws std::logic_error "<self>: <call> called <why>" unless `state` is one of `allowed`.
void check_call(std::string_view self, std::string_view call, State state,
                std::initializer_list<State> allowed);

}  // namespace dld::coupler
