// SPDX-License-Identifier: MIT
// The run file of a coupled run: one HDF5 file holding a copy of every part file the programs
// wrote (docs/architecture.md, "A coupled run"). The part files stay: the checkpoints resume them.
#pragma once
#include <string>
#include <vector>

namespace dld::coupler {

struct RunPart {
  std::string group;  ///< top-level group of the run file: "fluid", "membrane-0", ...
  std::string file;   ///< the part file, e.g. runs/x-fluid.h5
};

/// The parts of the run with output stem `stem` (runs/x): `<stem>-fluid.h5` as "fluid" and
/// `<stem>-<membrane>-k.h5` as "membrane-k" for k < peers (`membrane` is "cells" or "tracers").
std::vector<RunPart> run_parts(const std::string& stem, const std::string& membrane, int peers);

/// Writes `merged`: each part's root group (attributes included) copied to /<group>, with the
/// attribute source_file (the part's file name) on it and membrane_processes (the number of
/// "membrane-" groups) on the root. Written as `merged`.tmp and renamed, so `merged` is either
/// complete or untouched. A missing or unreadable part is an InputError naming it; nothing is
/// written then.
void merge_run_file(const std::vector<RunPart>& parts, const std::string& merged);

}  // namespace dld::coupler
