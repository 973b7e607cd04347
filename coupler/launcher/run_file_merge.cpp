// SPDX-License-Identifier: MIT
#include "coupler/launcher/run_file_merge.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <filesystem>

#include "shared/h5file.hpp"
#include "shared/input_error.hpp"

namespace dld::coupler {

namespace fs = std::filesystem;

std::vector<RunPart> run_parts(const std::string& stem, const std::string& membrane, int peers) {
  std::vector<RunPart> parts{{"fluid", stem + "-fluid.h5"}};
  for (int k = 0; k < peers; ++k) {
    parts.push_back({fmt::format("membrane-{}", k), fmt::format("{}-{}-{}.h5", stem, membrane, k)});
  }
  return parts;
}

void merge_run_file(const std::vector<RunPart>& parts, const std::string& merged) {
  // Every part is opened before anything is written: a missing one leaves no file behind.
  std::vector<H5File> sources;
  for (const RunPart& p : parts) {
    if (!fs::is_regular_file(p.file)) {
      throw InputError(
          fmt::format("{}: no such file (expected the {} part of the run)", p.file, p.group));
    }
    sources.emplace_back(p.file, H5File::Mode::kRead);
  }
  const std::string tmp = merged + ".tmp";
  try {
    H5File out(tmp, H5File::Mode::kCreate);
    std::int64_t membranes = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
      const std::string group = "/" + parts[i].group;
      out.copy_from(sources[i], "/", group);
      out.attribute(group, "source_file", fs::path(parts[i].file).filename().string());
      membranes += parts[i].group.starts_with("membrane-") ? 1 : 0;
    }
    // dld-analyze checks that every membrane group is there (a run file copied by hand may not).
    out.attribute("/", "membrane_processes", membranes);
    out.close();
    fs::rename(tmp, merged);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace dld::coupler
