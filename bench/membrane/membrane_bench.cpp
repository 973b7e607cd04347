// SPDX-License-Identifier: MIT
// Force evaluation per cell (2000 faces, r = 3.9 um at dx = 0.4 um) for each model, and contact
// search for 17 cells in the DLD box (cells:0 = walls and pillar only), with 1 and 2 OpenMP
// threads.
// Run from the build directory: bench/membrane/membrane_bench (meshes cached in cache/meshes).
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <omp.h>

#include <random>

#include "membrane/cell_set.hpp"
#include "membrane/contact.hpp"
#include "membrane/mesh_cache.hpp"
#include "membrane/model_registry.hpp"

namespace dld::membrane {
namespace {

const TriMesh& cell() {
  static const TriMesh m = [] {
    EvansFungShape s;
    s.radius = 9.75;
    TriMesh t = evans_fung_mesh(s, 2000, "cache/meshes");
    t.nodes.colwise() -= centroid(t.nodes);
    return t;
  }();
  return m;
}

AnyModel model(int which) {
  const TriMesh& m = cell();
  switch (which) {
    case 0:
      return SkalakModel(m, {1e-4, 0.5});
    case 1:
      return NeoHookeanModel(m, {1e-4});
    case 2:
      return BendingModel(m, {1e-5});
    case 3:
      return VolumePenalty(m, {1e-2});
    default:
      return AreaPenalty(m, {1e-2});
  }
}

void BM_CellForces(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const AnyModel mdl = model(static_cast<int>(state.range(0)));
  Points x = cell().nodes;
  x.row(0) *= 1.1;  // deformed, so every term works
  Points f = Points::Zero(3, x.cols());
  for (auto _ : state) {
    f.setZero();
    const double e = std::visit([&](const auto& m) { return m.add_forces(x, f); }, mdl);
    benchmark::DoNotOptimize(e);
    benchmark::DoNotOptimize(f.data());
  }
  static const char* names[] = {"skalak", "neo_hookean", "bending", "volume", "area"};
  state.SetLabel(fmt::format("{}, {} faces", names[state.range(0)], cell().face_count()));
}
BENCHMARK(BM_CellForces)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2}})
    ->ArgNames({"model", "threads"})
    ->Unit(benchmark::kMicrosecond);

/// 17 cells (Ht about 46 %) in the 80 x 80 x 12 box of dx = 0.4 um: two staggered layers on a
/// grid avoiding the pillar; neighbours overlap the contact range, as in a dense suspension.
Points suspension(int cells) {
  const TriMesh& m = cell();
  const DldCell box{80.0, 25.0, 12.0, 11.0};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 80.0);
  Points x(3, 0);
  int placed = 0;
  while (placed < cells) {
    const Eigen::Vector3d c(u(rng), u(rng), placed % 2 ? 8.3 : 3.7);
    if (box.pillar_distance(c.x(), c.y()) < 2.0) continue;
    x.conservativeResize(3, x.cols() + m.node_count());
    x.rightCols(m.node_count()) = m.nodes.colwise() + c;
    ++placed;
  }
  return x;
}

/// Membrane forces (Skalak + bending + volume) of 17 cells through CellSet, which spreads the
/// cells over the threads.
void BM_SuspensionForces(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  const TriMesh& m = cell();
  std::vector<AnyModel> models;
  models.emplace_back(SkalakModel(m, {1e-4, 0.5}));
  models.emplace_back(BendingModel(m, {1e-5}));
  models.emplace_back(VolumePenalty(m, {1e-2}));
  CellSet cells(m, MembraneMechanics({"skalak", "bending", "volume"}, std::move(models)));
  const Points x = suspension(17);
  for (int k = 0; k < 17; ++k)
    cells.add_cell(Points(x.middleCols(Eigen::Index{k} * m.node_count(), m.node_count())));
  Points f;
  for (auto _ : state) benchmark::DoNotOptimize(cells.compute_forces(f));
  state.SetLabel("17 cells x (skalak + bending + volume)");
}
BENCHMARK(BM_SuspensionForces)->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMicrosecond);

void BM_ContactSearch(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  const DldCell box{80.0, 25.0, 12.0, 11.0};
  const bool cells = state.range(1) != 0;
  const Contact contact(box, ContactParams{1.0, 1e-4, true, true, cells});
  const Points x = suspension(17);
  Points f = Points::Zero(3, x.cols());
  for (auto _ : state) {
    f.setZero();
    benchmark::DoNotOptimize(contact.add_forces(x, cell().node_count(), f));
  }
  state.SetLabel(
      fmt::format("17 cells, {} nodes, {} pairs in range", x.cols(), contact.last_pair_count()));
}
BENCHMARK(BM_ContactSearch)
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->ArgNames({"threads", "cells"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dld::membrane

BENCHMARK_MAIN();
