// SPDX-License-Identifier: MIT
// Helpers for the coupler tests: a scene, endpoints per transport, a raw PAIR peer that speaks
// bytes (to send what a broken program would), and a runner for one coupled run in threads.
#pragma once
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <numeric>
#include <optional>
#include <string>
#include <thread>
#include <vector>
#include <zmq.hpp>

#include "coupler/error.hpp"
#include "coupler/fluid_side.hpp"
#include "coupler/frame.hpp"
#include "coupler/membrane_side.hpp"
#include "tests/temp_dir.hpp"

namespace dld::coupler::test {

using namespace std::chrono_literals;

inline SceneIdentity test_scene(std::uint32_t cells) {
  SceneIdentity s;
  s.scene_hash = "sha256:0123456789abcdef";
  s.agreed = {{"dx_m", 0.4e-6, 1e-12},          {"dt_s", 2.1e-8, 1e-12},
              {"density_kg_m3", 1025.0, 1e-12}, {"lambda_m", 32e-6, 1e-12},
              {"radius_m", 8e-6, 1e-12},        {"depth_m", 4.4e-6, 1e-12},
              {"shift_m", 3.2e-6, 1e-12}};
  s.start_step = 0;
  s.total_cells = cells;
  return s;
}

/// Sets the agreed value `name` of a scene identity (it must be there).
inline void set_value(SceneIdentity& s, const std::string& name, double value) {
  for (AgreedValue& v : s.agreed)
    if (v.name == name) v.value = value;
}

/// Short timeouts: a test that waits for a timeout waits well under a second.
inline Options test_options(std::chrono::milliseconds timeout = 3000ms) {
  Options o;
  o.timeout = timeout;
  o.handshake_timeout = timeout;
  o.linger = 200ms;
  return o;
}

/// A fresh directory for ipc sockets, removed at the end of the test.
struct TempDir : dld::test::TempDir {
  TempDir() : dld::test::TempDir("dld-coupler") {}
};

enum class Kind { inproc, ipc, tcp };
inline std::string name(Kind k) {
  return k == Kind::inproc ? "inproc" : k == Kind::ipc ? "ipc" : "tcp";
}

/// Base endpoints the fluid binds: tcp only on 127.0.0.1 with a port the system picks.
inline std::vector<std::string> fluid_endpoints(Kind kind, std::size_t peers, const TempDir& dir) {
  static std::atomic<int> counter{0};
  std::vector<std::string> out;
  const int id = counter++;
  for (std::size_t k = 0; k < peers; ++k) {
    switch (kind) {
      case Kind::inproc:
        out.push_back(fmt::format("inproc://coupler-test-{}-{}", id, k));
        break;
      case Kind::ipc:
        out.push_back(fmt::format("ipc://{}/c{}", dir.path().string(), k));
        break;
      case Kind::tcp:
        out.push_back("tcp://127.0.0.1:*");
        break;
    }
  }
  return out;
}

/// Deterministic, full-mantissa test data; node 0 carries awkward values (-0, subnormal, huge).
inline void fill_nodes(std::uint64_t step, std::size_t first_node, std::vector<double>& x,
                       std::vector<double>& f) {
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double g = static_cast<double>(3 * first_node + i);
    x[i] = 40.0 * std::sin(0.37 * g + 0.011 * static_cast<double>(step)) + 1.0 / 3.0;
    f[i] = 1e-6 * std::cos(1.3 * g - 0.07 * static_cast<double>(step));
  }
  if (first_node == 0 && x.size() >= 3) {
    x[0] = -0.0;
    x[1] = 4.9e-324;
    f[2] = 1.7e308;
  }
}

/// The dummy fluid's answer: any fixed function of the received values will do.
inline void dummy_velocities(std::uint64_t step, std::span<const double> x,
                             std::span<const double> f, std::vector<double>& u) {
  u.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    u[i] = 1e-3 * x[i] - 0.5 * f[i] + 1e-9 * static_cast<double>(step);
  }
}

/// What each side saw during one coupled run.
struct RunRecord {
  std::vector<std::vector<double>> fluid_positions;  ///< per step, concatenated
  std::vector<std::vector<double>> fluid_forces;
  std::vector<std::vector<std::vector<double>>> membrane_velocities;  ///< [peer][step]
  std::string fluid_error;
  std::vector<std::string> membrane_errors;
  std::vector<int> shared_memory;  ///< per peer, as the membrane saw it (not vector<bool>: threads)
};

/// Runs `steps` exchanges between one fluid and one membrane per entry of `split` (the node counts
/// of that peer's cells), each side in its own thread; the membranes end the run.
inline RunRecord run_coupled(Kind kind, const std::vector<std::vector<std::uint32_t>>& split,
                             int steps, bool fluid_shm = true, bool membrane_shm = true) {
  TempDir dir;
  zmq::context_t context;
  std::uint32_t cells = 0;
  for (const auto& s : split) cells += static_cast<std::uint32_t>(s.size());
  FluidConfig fc{test_scene(cells), fluid_endpoints(kind, split.size(), dir), {}, test_options()};
  fc.options.shared_memory = fluid_shm;
  RunRecord rec;
  rec.membrane_velocities.resize(split.size());
  rec.membrane_errors.resize(split.size());
  rec.shared_memory.resize(split.size());
  auto fluid = std::make_unique<FluidSide>(fc, context);
  const auto endpoints = fluid->endpoints();

  std::thread fluid_thread([&] {
    try {
      fluid->initialize();
      std::vector<double> u;
      while (fluid->receive()) {
        rec.fluid_positions.emplace_back(fluid->positions().begin(), fluid->positions().end());
        rec.fluid_forces.emplace_back(fluid->forces().begin(), fluid->forces().end());
        dummy_velocities(fluid->step(), fluid->positions(), fluid->forces(), u);
        fluid->send_velocities(u);
      }
      fluid->finalize();
    } catch (const std::exception& e) {
      rec.fluid_error = e.what();
    }
  });
  std::vector<std::thread> membranes;
  std::uint32_t first_cell = 0;
  std::size_t first_node = 0;
  for (std::size_t k = 0; k < split.size(); ++k) {
    MembraneConfig mc{test_scene(cells),
                      endpoints[k],
                      "membrane-" + std::to_string(k),
                      static_cast<std::uint32_t>(k),
                      static_cast<std::uint32_t>(split.size()),
                      first_cell,
                      split[k],
                      test_options()};
    mc.options.shared_memory = membrane_shm;
    membranes.emplace_back([&rec, &context, mc, k, first_node, steps] {
      try {
        MembraneSide m(mc, context);
        m.initialize();
        rec.shared_memory[k] = m.shared_memory();
        const std::size_t n = 3 * m.node_count();
        std::vector<double> x(n), f(n), u(n);
        for (int s = 0; s < steps; ++s) {
          fill_nodes(m.step(), first_node, x, f);
          if (!m.advance(x, f, u)) break;
          rec.membrane_velocities[k].push_back(u);
        }
        m.finalize();
      } catch (const std::exception& e) {
        rec.membrane_errors[k] = e.what();
      }
    });
    first_cell += static_cast<std::uint32_t>(split[k].size());
    first_node += std::accumulate(split[k].begin(), split[k].end(), std::size_t{0});
  }
  for (auto& t : membranes) t.join();
  fluid_thread.join();
  fluid.reset();
  return rec;
}

/// A peer that speaks raw bytes over a PAIR socket: what a broken program would send.
class RawPeer {
 public:
  RawPeer(zmq::context_t& context, const std::string& endpoint, bool bind)
      : socket_(context, zmq::socket_type::pair) {
    socket_.set(zmq::sockopt::linger, 0);
    if (bind) {
      socket_.bind(endpoint);
      endpoint_ = socket_.get(zmq::sockopt::last_endpoint);
    } else {
      socket_.connect(endpoint);
      endpoint_ = endpoint;
    }
  }
  const std::string& endpoint() const { return endpoint_; }
  void send(zmq::message_t&& frame) { (void)socket_.send(frame, zmq::send_flags::none); }
  void send_bytes(const void* data, std::size_t size) {
    (void)socket_.send(zmq::const_buffer(data, size), zmq::send_flags::none);
  }
  std::optional<zmq::message_t> receive(std::chrono::milliseconds timeout = 3000ms) {
    zmq::pollitem_t item{static_cast<void*>(socket_), 0, ZMQ_POLLIN, 0};
    if (zmq::poll(&item, 1, timeout) <= 0) return std::nullopt;
    zmq::message_t m;
    (void)socket_.recv(m);
    return m;
  }
  /// The frame type of a received message (header already known to be well formed).
  static FrameType type_of(const zmq::message_t& m) {
    return read_header(m, Link{"test", "peer"}, 0).type;
  }

 private:
  zmq::socket_t socket_;
  std::string endpoint_;
};

/// The hello a correct membrane with these cells would send.
inline Handshake hello_for(const SceneIdentity& scene, std::vector<std::uint32_t> cells,
                           std::string name = "raw") {
  Handshake h;
  h.scene = scene;
  h.side_name = std::move(name);
  h.cell_nodes = std::move(cells);
  return h;
}

}  // namespace dld::coupler::test
