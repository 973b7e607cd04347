// SPDX-License-Identifier: MIT
// Reusable buffers for outgoing data frames. A frame of ~1 MB allocated afresh every step costs
// page faults on both the allocation and the first write; here ZeroMQ hands each buffer back
// (its free callback) once the bytes have left or the inproc peer dropped the message, and the
// next frame of that size reuses it. In lock-step two buffers per link reach a steady state.
#pragma once
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>
#include <zmq.hpp>

#include "coupler/frame.hpp"

namespace dld::coupler {

class FramePool {
 public:
  FramePool() = default;
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;
  /// Buffers still held by ZeroMQ (in flight, or kept by an inproc peer) are freed by ZeroMQ's
  /// callback later; the others now.
  ~FramePool();

  /// Like make_frame(): header written, payload for the caller to fill.
  zmq::message_t make(FrameType type, std::uint64_t step, std::size_t payload_bytes);

  std::size_t blocks() const { return blocks_.size(); }

 private:
  struct Block;
  static void release(void* data, void* hint) noexcept;

  std::vector<Block*> blocks_;
};

}  // namespace dld::coupler
