// SPDX-License-Identifier: MIT
// Allocator for the large per-node arrays (populations, force and velocity fields). The kernel
// reads 19 and writes 19 streams far apart in memory; with 4 KiB pages every stream crosses a
// page each 512 values and the TLB misses dominate a large box. Arrays of 4 MiB or more are
// aligned to 2 MiB and advised MADV_HUGEPAGE before their first touch, so Linux backs them with
// transparent huge pages where it allows (THP "madvise" or "always"); elsewhere the advice is a
// no-op and the array is an ordinary 64-byte-aligned block. The flag exists so the benchmark can
// measure both side by side (bench_fluid BM_PeriodicBox128).
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>

namespace dld::fluid {

template <typename T>
class HugePageAllocator {
 public:
  using value_type = T;
  using propagate_on_container_copy_assignment = std::true_type;
  using propagate_on_container_move_assignment = std::true_type;
  using propagate_on_container_swap = std::true_type;

  static constexpr std::size_t kHugePage = std::size_t{2} << 20;
  static constexpr std::size_t kThreshold = std::size_t{4} << 20;

  explicit HugePageAllocator(bool huge_pages = true) noexcept : huge_(huge_pages) {}
  template <typename U>
  explicit HugePageAllocator(const HugePageAllocator<U>& other) noexcept
      : huge_(other.huge_pages()) {}

  [[nodiscard]] bool huge_pages() const noexcept { return huge_; }

  T* allocate(std::size_t count) {
    const std::size_t bytes = count * sizeof(T);
    const bool huge = huge_ && bytes >= kThreshold;
    const std::size_t align = huge ? kHugePage : 64;
    void* p = std::aligned_alloc(align, (bytes + align - 1) / align * align);
    if (p == nullptr) throw std::bad_alloc();
    // Advice only: if the kernel refuses, the array simply keeps 4 KiB pages.
    if (huge) madvise(p, bytes, MADV_HUGEPAGE);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t /*count*/) noexcept { std::free(p); }

  friend bool operator==(const HugePageAllocator& a, const HugePageAllocator& b) noexcept {
    return a.huge_ == b.huge_;
  }

 private:
  bool huge_;
};

}  // namespace dld::fluid
