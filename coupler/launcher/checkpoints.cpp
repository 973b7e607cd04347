// SPDX-License-Identifier: MIT
#include "coupler/launcher/checkpoints.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

namespace fs = std::filesystem;

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

}  // namespace dld::coupler
