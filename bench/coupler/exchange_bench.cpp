// SPDX-License-Identifier: MIT
// Round-trip exchange per coupled step: the membrane sends positions and forces of C cells of
// 1002 nodes, the fluid (a thread that does no physics) answers with velocities. Both sides are
// threads of this program; ipc and tcp still go through the kernel as between two processes.
// Run: coupler_bench --benchmark_min_time=1 --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true   (figures in docs/performance.md (Coupler))
#include <benchmark/benchmark.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

#include "coupler/fluid_side.hpp"
#include "coupler/frame.hpp"
#include "coupler/membrane_side.hpp"

namespace dld::coupler {
namespace {

constexpr std::uint32_t kNodesPerCell = 1002;

SceneIdentity scene(std::uint32_t cells) {
  SceneIdentity s;
  s.scene_hash = "bench";
  s.agreed = {{"dx_m", 0.4e-6, 1e-12}, {"dt_s", 2e-8, 1e-12}, {"density_kg_m3", 1025, 1e-12}};
  s.total_cells = cells;
  return s;
}

// Transports: 0 inproc, 1 ipc with the data in the frames, 2 ipc with the data in shared
// memory, 3 tcp on loopback.
std::string endpoint(int transport, const std::filesystem::path& dir) {
  static std::atomic<int> counter{0};
  switch (transport) {
    case 0:
      return "inproc://bench-" + std::to_string(counter++);
    case 1:
    case 2:
      return "ipc://" + (dir / "coupler").string();
    default:
      return "tcp://127.0.0.1:*";
  }
}

// On a machine shared with other jobs the fastest repetition is the best estimate of the cost
// itself; the median says what a run sees.
double fastest(const std::vector<double>& v) {
  return *std::min_element(v.begin(), v.end());
}

const char* transport_name(int transport) {
  static const char* names[] = {"inproc", "ipc", "ipc+shm", "tcp"};
  return names[transport];
}

// api 0: the copying calls (advance(X, F, U), send_velocities(u) from the program's arrays);
// api 1: in place (positions_buffer()/forces_buffer(), exchange() views, velocities_buffer()),
// where the solvers would compute straight into the coupler's buffers.
void BM_Exchange(benchmark::State& state) {
  const int transport = static_cast<int>(state.range(0));
  const auto cells = static_cast<std::uint32_t>(state.range(1));
  const bool in_place = state.range(2) == 1;
  std::string tmp = (std::filesystem::temp_directory_path() / "dld-bench-XXXXXX").string();
  if (mkdtemp(tmp.data()) == nullptr) {
    state.SkipWithError("mkdtemp failed");
    return;
  }
  zmq::context_t context;
  Options options;
  options.timeout = std::chrono::seconds(10);
  options.shared_memory = transport == 2;
  FluidSide fluid({scene(cells), {endpoint(transport, tmp)}, {}, options}, context);
  std::thread fluid_thread([&] {
    fluid.initialize();
    std::vector<double> u;
    while (fluid.receive()) {  // no physics: only the exchange is timed
      if (in_place) {
        fluid.send_velocities(fluid.velocities_buffer());
      } else {
        u.resize(fluid.positions().size(), 0.25);
        fluid.send_velocities(u);
      }
    }
    fluid.finalize();
  });
  MembraneSide membrane({scene(cells), fluid.endpoints()[0], "membrane-0", 0, 1, 0,
                         std::vector<std::uint32_t>(cells, kNodesPerCell), options},
                        context);
  membrane.initialize();
  const bool membrane_shared = membrane.shared_memory();
  const std::size_t n = 3 * membrane.node_count();
  std::vector<double> x(n, 1.0), f(n, 0.5), u(n);
  for (auto _ : state) {
    if (in_place) {
      const auto view = membrane.exchange(membrane.positions_buffer(), membrane.forces_buffer());
      if (!view) state.SkipWithError("fluid ended the run");
      benchmark::DoNotOptimize(view->data());
    } else {
      if (!membrane.advance(x, f, u)) state.SkipWithError("fluid ended the run");
      benchmark::DoNotOptimize(u.data());
    }
  }
  membrane.finalize();
  fluid_thread.join();
  std::filesystem::remove_all(tmp);
  const double bytes = static_cast<double>(kHeaderBytes * 2 + step_payload_bytes(n / 3) +
                                           velocities_payload_bytes(n / 3));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  const std::size_t nodes = n / 3;
  state.counters["nodes"] = static_cast<double>(nodes);
  state.counters["KB_per_step"] = bytes / 1024.0;
  state.SetLabel(std::string(transport_name(transport)) + (in_place ? " in-place" : " copying"));
  if (transport == 2 && !membrane_shared) state.SkipWithError("shared memory was not used");
}
BENCHMARK(BM_Exchange)
    ->ArgNames({"transport", "cells", "api"})
    ->ArgsProduct({{0, 1, 2, 3}, {1, 3, 17}, {0, 1}})
    ->ComputeStatistics("min", fastest)
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

// The copies the codec makes on its own (encode one step frame, copy velocities out): the floor
// under any transport.
void BM_CodecCopies(benchmark::State& state) {
  const auto cells = static_cast<std::size_t>(state.range(0));
  const std::size_t n = 3 * cells * kNodesPerCell;
  std::vector<double> x(n, 1.0), f(n, 0.5), u(n);
  for (auto _ : state) {
    zmq::message_t step = encode_step(7, x, f);
    zmq::message_t reply = encode_velocities(7, u);
    const Link link{"bench", "bench"};
    const FrameHeader h = read_header(step, link, 7);
    std::memcpy(x.data(), read_nodes(step, h, n / 3, 2, link), n * sizeof(double));
    const FrameHeader r = read_header(reply, link, 7);
    std::memcpy(u.data(), read_nodes(reply, r, n / 3, 1, link), n * sizeof(double));
    benchmark::DoNotOptimize(x.data());
    benchmark::DoNotOptimize(u.data());
  }
}
BENCHMARK(BM_CodecCopies)->ArgName("cells")->Arg(1)->Arg(3)->Arg(17)->Unit(benchmark::kMicrosecond);

// The floor under the coupler: the same bytes over bare PAIR sockets, sent zero-copy from fixed
// buffers and never decoded.
void BM_BarePair(benchmark::State& state) {
  const int transport = static_cast<int>(state.range(0));
  const auto cells = static_cast<std::size_t>(state.range(1));
  const std::size_t n = cells * kNodesPerCell;
  std::string tmp = (std::filesystem::temp_directory_path() / "dld-bench-XXXXXX").string();
  if (mkdtemp(tmp.data()) == nullptr) {
    state.SkipWithError("mkdtemp failed");
    return;
  }
  zmq::context_t context;
  zmq::socket_t fluid(context, zmq::socket_type::pair);
  fluid.set(zmq::sockopt::linger, 0);
  fluid.bind(endpoint(transport, tmp));
  zmq::socket_t membrane(context, zmq::socket_type::pair);
  membrane.set(zmq::sockopt::linger, 0);
  membrane.connect(fluid.get(zmq::sockopt::last_endpoint));
  std::vector<std::byte> request(kHeaderBytes + step_payload_bytes(n));
  std::vector<std::byte> reply(kHeaderBytes + velocities_payload_bytes(n));
  std::thread fluid_thread([&] {
    for (;;) {
      zmq::message_t in;
      (void)fluid.recv(in);
      if (in.size() == 0) return;
      zmq::message_t out(
          reply.data(), reply.size(), [](void*, void*) {}, nullptr);
      (void)fluid.send(out, zmq::send_flags::none);
    }
  });
  for (auto _ : state) {
    zmq::message_t out(
        request.data(), request.size(), [](void*, void*) {}, nullptr);
    (void)membrane.send(out, zmq::send_flags::none);
    zmq::message_t in;
    (void)membrane.recv(in);
    benchmark::DoNotOptimize(in.data());
  }
  (void)membrane.send(zmq::message_t(), zmq::send_flags::none);
  fluid_thread.join();
  std::filesystem::remove_all(tmp);
  state.SetLabel(transport_name(transport));
}
BENCHMARK(BM_BarePair)
    ->ArgNames({"transport", "cells"})
    ->ArgsProduct({{0, 1, 3}, {1, 3, 17}})
    ->ComputeStatistics("min", fastest)
    ->UseRealTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace dld::coupler

BENCHMARK_MAIN();
