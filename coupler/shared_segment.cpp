// SPDX-License-Identifier: MIT
#include "coupler/shared_segment.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <utility>

#include "coupler/error.hpp"

namespace dld::coupler {

namespace {

std::byte* map(int fd, std::size_t bytes) {
  void* at = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  return at == MAP_FAILED ? nullptr : static_cast<std::byte*>(at);
}

}  // namespace

SharedSegment SharedSegment::create(std::size_t bytes, const std::string& self) {
  static std::atomic<int> counter{0};
  SharedSegment segment;
  segment.name_ = fmt::format("/dld-coupler-{}-{}", getpid(), counter++);
  const int fd = shm_open(segment.name_.c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  if (fd < 0) {
    throw CouplerError(fmt::format("{}: cannot create shared memory '{}': {}", self, segment.name_,
                                   std::strerror(errno)));
  }
  segment.owner_ = true;
  if (ftruncate(fd, static_cast<off_t>(bytes)) != 0 ||
      (segment.data_ = map(fd, bytes)) == nullptr) {
    const int error = errno;
    close(fd);
    throw CouplerError(fmt::format("{}: cannot size or map shared memory '{}' of {} bytes: {}",
                                   self, segment.name_, bytes, std::strerror(error)));
  }
  close(fd);
  segment.size_ = bytes;
  return segment;
}

SharedSegment SharedSegment::open(const std::string& name, std::size_t bytes,
                                  const std::string& self) {
  SharedSegment segment;
  segment.name_ = name;
  const int fd = shm_open(name.c_str(), O_RDWR, 0);
  if (fd < 0) {
    throw CouplerError(fmt::format("{}: cannot open the peer's shared memory '{}': {}", self, name,
                                   std::strerror(errno)));
  }
  struct stat info {};
  if (fstat(fd, &info) != 0 || static_cast<std::size_t>(info.st_size) < bytes) {
    close(fd);
    throw CouplerError(fmt::format("{}: the peer's shared memory '{}' has {} bytes, expected {}",
                                   self, name, info.st_size, bytes));
  }
  segment.data_ = map(fd, bytes);
  if (segment.data_ == nullptr) {
    const int error = errno;
    close(fd);
    throw CouplerError(fmt::format("{}: cannot map the peer's shared memory '{}': {}", self, name,
                                   std::strerror(error)));
  }
  close(fd);
  segment.size_ = bytes;
  return segment;
}

SharedSegment::SharedSegment(SharedSegment&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      name_(std::move(other.name_)),
      owner_(std::exchange(other.owner_, false)) {}

SharedSegment& SharedSegment::operator=(SharedSegment&& other) noexcept {
  if (this != &other) {
    this->~SharedSegment();
    new (this) SharedSegment(std::move(other));
  }
  return *this;
}

SharedSegment::~SharedSegment() {
  unlink();
  if (data_ != nullptr) {
    munmap(data_, size_);
  }
}

void SharedSegment::unlink() noexcept {
  if (owner_) {
    shm_unlink(name_.c_str());
  }
  owner_ = false;
}

}  // namespace dld::coupler
