// SPDX-License-Identifier: MIT
// Which checkpoints a resumed run starts from: every program keeps its newest checkpoint and the
// one before (.prev); the run resumes at the newest step all of them have.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace dld::coupler {

/// Step of a checkpoint file (attribute `step` of `group`), or -1 if missing or unreadable.
std::int64_t checkpoint_step(const std::string& path, const std::string& group);

/// For each (file, group), the file (itself or its .prev) at the newest step all of them have.
/// Throws dld::InputError naming each file and why it cannot be used when there is none.
std::vector<std::string> common_checkpoint(
    const std::vector<std::pair<std::string, std::string>>& sides);

}  // namespace dld::coupler
