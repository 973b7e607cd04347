// SPDX-License-Identifier: MIT
// Fluid update rate (MLUPS = million fluid-node updates per second) of the production kernel on
// the 80x80x12 DLD cell and a 128^3 periodic box, next to the naive baseline loop, with 1 and 2
// OpenMP threads; and the roofline this machine's memory bandwidth allows for our scheme.
// Run: build/bench/fluid/bench_fluid   (figures go to docs/performance.md)
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "fluid/collision/trt.hpp"
#include "fluid/fluid_solver.hpp"
#include "fluid/immersed_boundary.hpp"
#include "fluid/viscosity_contrast.hpp"
#include "tests/common/base_scene.hpp"
#ifdef DLD_BENCH_CELLS
#include "membrane/sphere_mesh.hpp"
#endif
#include "memory_bandwidth.hpp"
#include "naive_bgk.hpp"
#include "shared/h5file.hpp"
#include "shared/scene.hpp"

namespace {

using dld::fluid::FluidConfig;
using dld::fluid::FluidSolver;

// Two arrays of 19 doubles: each update reads 19 values and writes 19, and every written line is
// first read (write-allocate). The bandwidth measurement counts the same three kinds of traffic,
// so the roofline below is consistent: 3 x 19 x 8 = 456 bytes per node update.
constexpr double kBytesPerUpdate = 3 * 19 * 8;
constexpr double kStateBytesPerNode = 2 * 19 * 8 + 1;  // two population arrays + solid flag

FluidConfig dld_config() {
  const dld::Scene s = dld::parse_scene(dld::testing::kBaseScene, "bench.toml");
  return dld::fluid::fluid_config(s);
}

FluidConfig periodic_box(int n) {
  FluidConfig c;
  c.domain.nx = c.domain.ny = c.domain.nz = n;
  c.domain.walls_z = false;
  c.force_x = 1e-6;
  return c;
}

void report(benchmark::State& state, double nodes) {
  state.counters["MLUPS"] = benchmark::Counter(
      nodes * static_cast<double>(state.iterations()) / 1e6, benchmark::Counter::kIsRate);
}

// Second argument: 1 = per-node arrays on huge pages (the default), 0 = ordinary pages.
void BM_DldCell(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  auto config = dld_config();
  config.huge_pages = state.range(1) != 0;
  FluidSolver s(config);
  for (int i = 0; i < 20; ++i) s.step();
  for (auto _ : state) s.step();
  report(state, static_cast<double>(s.lattice().fluid_nodes()));
}
BENCHMARK(BM_DldCell)
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->ArgNames({"threads", "huge"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The lattice kernel alone (TRT, uniform force, no fields; bounce-back and ghosts not refreshed:
// a timing, not a flow), one thread, on n x n x 12 boxes of growing size: whether its pace per
// node depends on where its two population arrays fit (L2, L3, memory) tells whether it is bound
// by cache traffic on this host. Argument 0: the DLD cell's lattice instead (its runs cut by the
// pillar), the same loop.
void BM_KernelByBoxSize(benchmark::State& state) {
  omp_set_num_threads(1);
  dld::fluid::Domain d = dld_config().domain;
  if (state.range(0) > 0) {
    d = dld::fluid::Domain{};
    d.nx = d.ny = static_cast<int>(state.range(0));
    d.nz = 12;
    d.walls_z = false;
  }
  const dld::fluid::Lattice L(d);
  const std::size_t n = L.padded_size();
  std::vector<double> f(n * 19 + dld::fluid::kPopulationPadding, 1.0 / 19);
  std::vector<double> g = f;
  dld::fluid::KernelParams p;
  p.force[0] = 1e-6;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        dld::fluid::stream_collide<dld::fluid::Trt, false, false>(L, f.data(), g.data(), p));
    f.swap(g);
  }
  report(state, static_cast<double>(L.fluid_nodes()));
  state.counters["MB"] = 2.0 * 19 * 8 * static_cast<double>(n) / 1e6;
  int blocks = 0;  // 8-node blocks the kernel updates, masked tails included
  for (const auto& run : L.segments()) blocks += (run.length + 7) / 8;
  state.counters["blocks"] = static_cast<double>(blocks);
}
BENCHMARK(BM_KernelByBoxSize)
    ->Arg(0)
    ->Arg(16)
    ->Arg(24)
    ->Arg(32)
    ->Arg(48)
    ->Arg(80)
    ->Arg(128)
    ->Arg(256)
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

void BM_PeriodicBox128(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  auto config = periodic_box(128);
  config.huge_pages = state.range(1) != 0;
  FluidSolver s(config);
  for (int i = 0; i < 3; ++i) s.step();
  for (auto _ : state) s.step();
  report(state, static_cast<double>(s.lattice().fluid_nodes()));
}
BENCHMARK(BM_PeriodicBox128)
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->ArgNames({"threads", "huge"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_NaiveBgkBox128(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  dld::bench::NaiveBgk s(128, 128, 128, 1.0);
  s.step();
  for (auto _ : state) s.step();
  report(state, static_cast<double>(s.nodes()));
}
BENCHMARK(BM_NaiveBgkBox128)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// Immersed boundary for `count` cells of 1002 markers at dx = 0.4 um (17: the 45.6 % haematocrit
// case): flat clouds of radius 9 nodes spread over the fluid part of the box.
std::vector<double> marker_cells(const dld::fluid::Lattice& L, int count) {
  std::vector<double> x;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int cells = 0;
  while (cells < count) {
    const double c[3] = {u(rng) * L.nx(), u(rng) * L.ny(), 0.5 * L.nz()};
    if (L.domain().in_pillar(c[0], c[1]) || L.domain().in_pillar(c[0] + 9, c[1]) ||
        L.domain().in_pillar(c[0] - 9, c[1]) || L.domain().in_pillar(c[0], c[1] + 9) ||
        L.domain().in_pillar(c[0], c[1] - 9))
      continue;
    for (int m = 0; m < 1002; ++m) {  // flat disc-like cloud: radius 9, thickness 5 nodes
      const double phi = 2 * M_PI * u(rng), r = 9 * std::sqrt(u(rng));
      x.insert(x.end(),
               {c[0] + r * std::cos(phi), c[1] + r * std::sin(phi), c[2] + 2.5 * (2 * u(rng) - 1)});
    }
    ++cells;
  }
  return x;
}

// Args: threads, cells.
void BM_IbSpread(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  const dld::fluid::ImmersedBoundary ib(s.lattice(), dld::fluid::IbKernel::kPeskin4);
  const auto x = marker_cells(s.lattice(), static_cast<int>(state.range(1)));
  const std::vector<double> f(x.size(), 1e-6);
  for (auto _ : state) ib.spread(x, f, s.force_field());
  const std::size_t markers = x.size() / 3;
  state.counters["markers"] = static_cast<double>(markers);
}
BENCHMARK(BM_IbSpread)
    ->ArgsProduct({{1, 2}, {1, 17}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// Interpolation alone: the velocity field is what a coupled step's kernel leaves behind.
void BM_IbInterpolate(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  const dld::fluid::ImmersedBoundary ib(s.lattice(), dld::fluid::IbKernel::kPeskin4);
  const auto x = marker_cells(s.lattice(), static_cast<int>(state.range(1)));
  std::vector<double> u(x.size());
  s.force_field();
  s.step();
  for (auto _ : state) ib.interpolate(x, s.velocity_field(), u);
  const std::size_t markers = x.size() / 3;
  state.counters["markers"] = static_cast<double>(markers);
}
BENCHMARK(BM_IbInterpolate)
    ->ArgsProduct({{1, 2}, {1, 17}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// Interpolation in a held step (fast's [coupling] force_every > 1 with spread_held): the markers
// have moved since the last spread, so its footprints do not serve.
void BM_IbInterpolateMoved(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  const dld::fluid::ImmersedBoundary ib(s.lattice(), dld::fluid::IbKernel::kPeskin4);
  auto x = marker_cells(s.lattice(), static_cast<int>(state.range(1)));
  const std::vector<double> f(x.size(), 1e-6);
  std::vector<double> u(x.size());
  ib.spread(x, f, s.force_field());
  s.step();
  for (double& v : x) v += 1e-3;  // about four held steps of a dense run's fastest nodes
  for (auto _ : state) ib.interpolate(x, s.velocity_field(), u);
  const std::size_t markers = x.size() / 3;
  state.counters["markers"] = static_cast<double>(markers);
}
BENCHMARK(BM_IbInterpolateMoved)
    ->ArgsProduct({{1, 2}, {1, 17}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// The immersed boundary of one coupled step: spread at new positions, then interpolate at the same
// positions (the markers move by a tiny amount between iterations, as they do between steps).
void time_coupled_ib(benchmark::State& state, FluidSolver& s,
                     const dld::fluid::ImmersedBoundary& ib, std::vector<double>& x) {
  const std::vector<double> f(x.size(), 1e-6);
  std::vector<double> u(x.size());
  s.force_field();
  s.step();
  double dx = 1e-4;
  for (auto _ : state) {
    for (double& v : x) v += dx;
    dx = -dx;
    ib.spread(x, f, s.force_field());
    ib.interpolate(x, s.velocity_field(), u);
  }
}

void BM_IbCoupledStep(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  const dld::fluid::ImmersedBoundary ib(s.lattice(), dld::fluid::IbKernel::kPeskin4);
  auto x = marker_cells(s.lattice(), static_cast<int>(state.range(1)));
  time_coupled_ib(state, s, ib, x);
  const std::size_t markers = x.size() / 3;
  state.counters["markers"] = static_cast<double>(markers);
}
BENCHMARK(BM_IbCoupledStep)
    ->ArgsProduct({{1, 2}, {1, 17}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// The same on a production run's markers (the positions of a membrane checkpoint, with cells
// squeezing past the pillar: the near-solid stencils the clouds above avoid; and y many boxes
// away after a displaced run). Registered only when
// DLD_BENCH_SCENE (the run's scene.toml) and DLD_BENCH_POSITIONS (its run-cells-K.ckpt.h5) are set:
//   DLD_BENCH_SCENE=runs/.../scene.toml DLD_BENCH_POSITIONS=runs/.../run-cells-0.ckpt.h5
//   build/bench/fluid/bench_fluid --benchmark_filter=BM_IbCoupledStepOfRun (the two set first)
struct RunMarkers {
  RunMarkers(const std::string& scene_file, const std::string& positions_file)
      : solver(dld::fluid::fluid_config(dld::load_scene(scene_file))),
        ib(solver.lattice(), dld::fluid::IbKernel::kPeskin4),
        x(dld::H5File(positions_file, dld::H5File::Mode::kRead).read("membrane/positions")) {}
  FluidSolver solver;
  dld::fluid::ImmersedBoundary ib;
  std::vector<double> x;
};

void BM_IbCoupledStepOfRun(benchmark::State& state, const std::string& scene_file,
                           const std::string& positions_file) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  RunMarkers run(scene_file, positions_file);
  const dld::fluid::ImmersedBoundary& ib = run.ib;
  std::vector<double>& x = run.x;
  time_coupled_ib(state, run.solver, ib, x);
  std::size_t separable = 0, split = 0, masked = 0, markers = x.size() / 3;
  for (std::size_t m = 0; m < markers; ++m) {
    dld::fluid::IbFootprint<4> fp;
    dld::fluid::IbSplitFootprint<4> sp;
    dld::fluid::IbMaskedFootprint<4> mp;
    if (ib.footprint<4>(&x[3 * m], fp))
      ++separable;
    else if (ib.split_footprint<4>(&x[3 * m], sp))
      ++split;
    else if (ib.masked_footprint<4>(&x[3 * m], mp))
      ++masked;
  }
  state.counters["markers"] = static_cast<double>(markers);
  state.counters["split"] = static_cast<double>(split);
  state.counters["masked"] = static_cast<double>(masked);
  state.counters["stencil"] = static_cast<double>(markers - separable - split - masked);
}

// A held step's interpolation (`fast`) on a production run's markers: spread once, then interpolate
// at the markers moved since. Registered with BM_IbCoupledStepOfRun.
void BM_IbHeldStepOfRun(benchmark::State& state, const std::string& scene_file,
                        const std::string& positions_file) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  RunMarkers run(scene_file, positions_file);
  std::vector<double>& x = run.x;
  const std::vector<double> f(x.size(), 1e-6);
  std::vector<double> u(x.size());
  run.ib.spread(x, f, run.solver.force_field());
  run.solver.step();
  for (double& v : x) v += 1e-3;  // about four held steps of a dense run's fastest nodes
  for (auto _ : state) run.ib.interpolate(x, run.solver.velocity_field(), u);
  const std::size_t markers = x.size() / 3;
  state.counters["markers"] = static_cast<double>(markers);
}

void register_run_benchmark() {
  const char* scene = std::getenv("DLD_BENCH_SCENE");
  const char* positions = std::getenv("DLD_BENCH_POSITIONS");
  if (scene == nullptr || positions == nullptr) return;
  benchmark::RegisterBenchmark("BM_IbCoupledStepOfRun", BM_IbCoupledStepOfRun, std::string(scene),
                               std::string(positions))
      ->Arg(1)
      ->Arg(2)
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_IbHeldStepOfRun", BM_IbHeldStepOfRun, std::string(scene),
                               std::string(positions))
      ->Arg(1)
      ->UseRealTime()
      ->Unit(benchmark::kMicrosecond);
}
const bool kRunBenchmarkRegistered = (register_run_benchmark(), true);

#ifdef DLD_BENCH_CELLS
// The inside/outside viscosity field of one coupled step for `cells` closed cells: icospheres of
// 1280 faces flattened to RBC proportions (radius 9.75 nodes, thickness 0.35 of the width: the
// dx = 0.4 um cell), centred like marker_cells. Args: threads, cells.
void BM_ViscosityField(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  const int cells = static_cast<int>(state.range(1));
  const dld::membrane::TriMesh m = dld::membrane::icosphere(3, 9.75);
  const auto centres = marker_cells(s.lattice(), cells);  // first marker of each cloud ~ centre
  std::vector<double> x;
  std::vector<std::uint32_t> nodes, faces, ids;
  for (int c = 0; c < cells; ++c) {
    const double* o = &centres[std::size_t{3} * 1002 * static_cast<std::size_t>(c)];
    for (int n = 0; n < m.node_count(); ++n)
      x.insert(x.end(), {o[0] + m.nodes(0, n), o[1] + m.nodes(1, n),
                         0.5 * s.lattice().nz() + 0.35 * m.nodes(2, n)});
    nodes.push_back(static_cast<std::uint32_t>(m.node_count()));
    faces.push_back(static_cast<std::uint32_t>(m.face_count()));
    const auto local = dld::membrane::face_indices(m);
    ids.insert(ids.end(), local.begin(), local.end());
  }
  dld::fluid::ViscosityContrast vc(s.lattice(), 1.0, 3.0, nodes, faces, ids);
  double dx = 1e-3;
  for (auto _ : state) {
    for (double& v : x) v += dx;
    dx = -dx;
    vc.update(x, s.relaxation_field());
  }
  state.counters["inside_nodes"] = static_cast<double>(vc.inside_nodes().size());
}
BENCHMARK(BM_ViscosityField)
    ->ArgsProduct({{1, 2}, {1, 17}})
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);
#endif

// The lattice step of a coupled run (force field in, velocity field out; second argument 1: with
// the per-node relaxation of a viscosity contrast too) against the plain one.
void BM_DldCellStepWithForceField(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(dld_config());
  s.force_field();
  if (state.range(1) != 0) {
    dld::fluid::RelaxationField& r = s.relaxation_field();
    for (std::size_t n = 0; n < r.size(); n += 7) r.set(n, 3.0);  // some nodes "inside"
  }
  s.step();
  for (auto _ : state) s.step();
  report(state, static_cast<double>(s.lattice().fluid_nodes()));
}
BENCHMARK(BM_DldCellStepWithForceField)
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->ArgNames({"threads", "relaxation"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The coupled lattice step (force and relaxation fields) for each collision operator; second
// argument: the operator's index in dld::kCollisionNames (0 bgk, 1 trt, 2 mrt).
void BM_DldCellCollision(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  auto config = dld_config();
  config.collision = static_cast<dld::CollisionKind>(state.range(1));
  FluidSolver s(config);
  s.force_field();
  dld::fluid::RelaxationField& r = s.relaxation_field();
  for (std::size_t n = 0; n < r.size(); n += 7) r.set(n, 3.0);
  s.step();
  for (auto _ : state) s.step();
  report(state, static_cast<double>(s.lattice().fluid_nodes()));
  state.SetLabel(std::string(dld::kCollisionNames[static_cast<std::size_t>(state.range(1))]));
}
BENCHMARK(BM_DldCellCollision)
    ->ArgsProduct({{1, 2}, {0, 1, 2}})
    ->ArgNames({"threads", "collision"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_MemoryBandwidth(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  double bw = 0;
  for (auto _ : state) bw = dld::bench::measured_bandwidth_gb_s();
  state.counters["GB/s"] = bw;
  state.counters["roofline_MLUPS"] = bw * 1e9 / kBytesPerUpdate / 1e6;
}
BENCHMARK(BM_MemoryBandwidth)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The roofline fraction from paired measurements: each round times a triad pass and then ten
// steps of the 128^3 box, back to back, so both see the same state of this shared machine (its
// bandwidth alone varied 43-85 GB/s within minutes on 2026-11-30). Reports the median, lowest and
// highest fraction over the rounds.
void BM_RooflineFraction128(benchmark::State& state) {
  omp_set_num_threads(static_cast<int>(state.range(0)));
  FluidSolver s(periodic_box(128));
  for (int i = 0; i < 3; ++i) s.step();
  const double nodes = static_cast<double>(s.lattice().fluid_nodes());
  std::vector<double> fractions;
  for (auto _ : state) {
    const double bw = dld::bench::measured_bandwidth_gb_s();
    const double t0 = omp_get_wtime();
    constexpr int kSteps = 10;
    for (int i = 0; i < kSteps; ++i) s.step();
    const double mlups = nodes * kSteps / (omp_get_wtime() - t0) / 1e6;
    fractions.push_back(mlups / (bw * 1e9 / kBytesPerUpdate / 1e6));
  }
  std::sort(fractions.begin(), fractions.end());
  state.counters["fraction_median"] = fractions[fractions.size() / 2];
  state.counters["fraction_min"] = fractions.front();
  state.counters["fraction_max"] = fractions.back();
}
BENCHMARK(BM_RooflineFraction128)
    ->Arg(1)
    ->Arg(2)
    ->Iterations(5)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  std::printf("bytes moved per node update (two arrays, double, with write-allocate): %.0f\n",
              kBytesPerUpdate);
  std::printf(
      "fluid state: %.0f bytes per node (two population arrays of 19 doubles + solid flag)\n",
      kStateBytesPerNode);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
