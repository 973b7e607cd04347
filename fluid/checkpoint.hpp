// SPDX-License-Identifier: MIT
// Fluid checkpoints: the populations and the solver's memory (step, lateral force and its
// controller) in an HDF5 file, written through a temporary file and a rename so that the previous
// checkpoint stays intact until the new one is complete; the one before is kept as `path`.prev. A
// checkpoint belongs to one scene (its hash) and one lattice; reading another scene's checkpoint is
// an error naming the file and field.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "fluid/fluid_solver.hpp"
#include "shared/scene.hpp"

namespace dld::fluid {

/// `timeseries`: the run file's /timeseries rows so far (kTimeseriesColumns per row), kept so that
/// a resumed run file starts with them.
void write_checkpoint(const std::string& path, const Scene& scene, const FluidSolver& solver,
                      const std::vector<double>& timeseries = {});
/// Restores `solver` from `path`; returns the step it was written at. Throws InputError. With
/// `timeseries`, the rows kept with the checkpoint (none for a checkpoint written without them).
std::int64_t read_checkpoint(const std::string& path, const Scene& scene, FluidSolver& solver,
                             std::vector<double>* timeseries = nullptr);

}  // namespace dld::fluid
