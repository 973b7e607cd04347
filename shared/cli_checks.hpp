// SPDX-License-Identifier: MIT
// Command-line checks shared by the programs (CLI11): a step count is a whole number in a stated
// range, named in the error, never a 300-digit range nor a silently clamped 2^63 - 1.
#pragma once
#include <CLI/CLI.hpp>
#include <charconv>
#include <cstdint>
#include <string>
#include <type_traits>

namespace dld {

/// Largest step count a program accepts: 10^15 steps is decades of any machine.
inline constexpr std::int64_t kMaxSteps = 1'000'000'000'000'000;

/// CLI11 check for a step count: digits only, 1 to kMaxSteps ("0" too with allow_zero).
inline CLI::Validator step_count(bool allow_zero = false) {
  return CLI::Validator(
      [allow_zero](std::string& s) -> std::string {
        std::int64_t v = 0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        const std::int64_t low = allow_zero ? 0 : 1;
        if (ec != std::errc() || end != s.data() + s.size() || v < low || v > kMaxSteps) {
          return "expected a whole number of steps from " + std::to_string(low) + " to " +
                 std::to_string(kMaxSteps) + ", got '" + s + "'";
        }
        return {};
      },
      allow_zero ? "STEPS (0..1e15)" : "STEPS (1..1e15)");
}

/// The checkpoint options every coupled program takes (dld-fluid, dld-membrane; dld-run passes
/// them on): --checkpoint FILE, --checkpoint-every STEPS, --resume FILE (dld-membrane: FILE...,
/// the checkpoints of every process of any split, membrane/run_checkpoint.hpp).
template <class ResumeFiles>
void add_checkpoint_options(CLI::App& app, std::string& file, std::int64_t& every,
                            ResumeFiles& resume) {
  app.add_option(
      "--checkpoint", file,
      "coupled mode: checkpoint file, written when the run ends (and see --checkpoint-every)");
  app.add_option("--checkpoint-every", every,
                 "coupled mode: steps between checkpoints (0: only at the end)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--resume", resume,
                 std::is_same_v<ResumeFiles, std::string>
                     ? "coupled mode: start from this checkpoint"
                     : "coupled mode: start from these checkpoints of one step (this process's "
                       "own, or every process's of a run split another way)");
}

}  // namespace dld
