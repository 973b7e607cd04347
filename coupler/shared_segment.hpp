// SPDX-License-Identifier: MIT
// A POSIX shared-memory segment for the ipc data path: node arrays are written once into memory
// both processes map, and only small frames cross the socket. Over a Unix socket a ~1.2 MB round
// trip costs two kernel copies and many wake-ups per step; through the segment it costs none.
#pragma once
#include <cstddef>
#include <string>

namespace dld::coupler {

/// A peer's segment holds three node arrays of 3 doubles per node, in this order: positions and
/// forces written by the membrane, velocities written by the fluid.
enum class SegmentArray : std::size_t { kPositions = 0, kForces = 1, kVelocities = 2 };
inline constexpr std::size_t kSegmentArrays = 3;

/// Where an array starts, in doubles from the segment's start, for a peer of `nodes` nodes.
constexpr std::size_t segment_offset(SegmentArray a, std::size_t nodes) {
  return static_cast<std::size_t>(a) * 3 * nodes;
}
/// Bytes of a peer's segment.
constexpr std::size_t segment_bytes(std::size_t nodes) {
  return kSegmentArrays * 3 * sizeof(double) * nodes;
}

class SharedSegment {
 public:
  /// Creates a new segment of `bytes` under a fresh name ("/dld-coupler-<pid>-<n>"). Throws
  /// CouplerError naming `self` if the system refuses.
  static SharedSegment create(std::size_t bytes, const std::string& self);
  /// Maps the segment `name` made by the peer; throws CouplerError if it is missing or smaller.
  static SharedSegment open(const std::string& name, std::size_t bytes, const std::string& self);

  SharedSegment() = default;
  SharedSegment(SharedSegment&& other) noexcept;
  SharedSegment& operator=(SharedSegment&& other) noexcept;
  SharedSegment(const SharedSegment&) = delete;
  SharedSegment& operator=(const SharedSegment&) = delete;
  ~SharedSegment();

  /// Removes the name (the mapping stays): once both sides have mapped it, nothing can leak.
  void unlink() noexcept;
  /// For a segment opened from a peer: throws CouplerError naming `self` and `peer` if the peer
  /// has shrunk it below the mapped size (touching the lost pages would be a SIGBUS).
  void require_size(const std::string& self, const std::string& peer) const;

  bool mapped() const { return data_ != nullptr; }
  std::byte* data() const { return data_; }
  /// One of the node arrays of a peer of `nodes` nodes (see SegmentArray).
  double* array(SegmentArray a, std::size_t nodes) const {
    return reinterpret_cast<double*>(data_) + segment_offset(a, nodes);
  }
  std::size_t size() const { return size_; }
  const std::string& name() const { return name_; }

 private:
  std::byte* data_ = nullptr;
  std::size_t size_ = 0;
  std::string name_;
  bool owner_ = false;  // created here: unlink on destruction if still linked
  int fd_ = -1;         // opened from a peer: kept to check its size (the peer unlinks the name)
};

}  // namespace dld::coupler
