// SPDX-License-Identifier: MIT
#include "coupler/frame_pool.hpp"

namespace dld::coupler {

namespace {
// Block states. ZeroMQ's callback may run on its I/O thread or the inproc peer's thread, so a
// block changes hands only through compare-and-swap.
constexpr int kFree = 0;
constexpr int kInUse = 1;
constexpr int kOrphan = 2;  // in use by ZeroMQ while the pool is gone: the callback deletes it
// More blocks than this means frames are not coming back; plain frames are then used instead.
constexpr std::size_t kMaxBlocks = 4;
}  // namespace

struct FramePool::Block {
  explicit Block(std::size_t bytes) : capacity(bytes), data(new std::byte[bytes]) {}
  std::atomic<int> state{kFree};
  std::size_t capacity;
  std::unique_ptr<std::byte[]> data;
};

void FramePool::release(void* /*data*/, void* hint) noexcept {
  auto* block = static_cast<Block*>(hint);
  int expected = kInUse;
  if (!block->state.compare_exchange_strong(expected, kFree)) {
    delete block;  // orphaned
  }
}

FramePool::~FramePool() {
  for (Block* block : blocks_) {
    int expected = kInUse;
    if (block->state.compare_exchange_strong(expected, kOrphan)) {
      continue;
    }
    delete block;  // free: nobody else holds it
  }
}

zmq::message_t FramePool::make(FrameType type, std::uint64_t step, std::size_t payload_bytes) {
  const std::size_t bytes = kHeaderBytes + payload_bytes;
  Block* chosen = nullptr;
  for (Block*& block : blocks_) {
    int expected = kFree;
    if (!block->state.compare_exchange_strong(expected, kInUse)) {
      continue;
    }
    if (block->capacity < bytes) {  // free and too small: only the pool can see it, replace it
      delete block;
      block = new Block(bytes);
      block->state = kInUse;
    }
    chosen = block;
    break;
  }
  if (chosen == nullptr) {
    if (blocks_.size() >= kMaxBlocks) {
      return make_frame(type, step, payload_bytes);
    }
    chosen = blocks_.emplace_back(new Block(bytes));
    chosen->state = kInUse;
  }
  write_header(chosen->data.get(), type, step, payload_bytes);
  return zmq::message_t(chosen->data.get(), bytes, &FramePool::release, chosen);
}

}  // namespace dld::coupler
