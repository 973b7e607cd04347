// SPDX-License-Identifier: MIT
#include "coupler/shared_segment.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <signal.h>
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

// Names this process created and has not unlinked yet. A program stopped by SIGINT or SIGTERM
// before its peer mapped the segment (before the welcome; afterwards the name is gone) would
// leave it in /dev/shm: while any is linked, those signals unlink them first, unless the program
// handles the signal itself. Fixed slots, so that the handler touches no allocator.
constexpr int kSlots = 16;
constexpr std::size_t kNameBytes = 64;
char g_linked[kSlots][kNameBytes] = {};

void unlink_and_die(int sig) {
  for (auto& name : g_linked)
    if (name[0] != '\0') shm_unlink(name);  // unlink(2) of /dev/shm/<name> on Linux
  signal(sig, SIG_DFL);
  raise(sig);
}

void remember(const std::string& name) {
  static std::atomic<bool> installed{false};
  if (!installed.exchange(true)) {
    for (const int sig : {SIGINT, SIGTERM}) {
      struct sigaction now {};
      if (sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_DFL)
        signal(sig, unlink_and_die);
    }
  }
  for (auto& slot : g_linked)
    if (slot[0] == '\0' && name.size() < kNameBytes) {
      std::memcpy(slot, name.c_str(), name.size() + 1);
      return;
    }
}

void forget(const std::string& name) {
  for (auto& slot : g_linked)
    if (name == slot) slot[0] = '\0';
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
  remember(segment.name_);
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
  segment.fd_ = fd;
  segment.size_ = bytes;
  return segment;
}

SharedSegment::SharedSegment(SharedSegment&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)),
      size_(std::exchange(other.size_, 0)),
      name_(std::move(other.name_)),
      owner_(std::exchange(other.owner_, false)),
      fd_(std::exchange(other.fd_, -1)) {}

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
  if (fd_ >= 0) close(fd_);
}

void SharedSegment::require_size(const std::string& self, const std::string& peer) const {
  struct stat info {};
  if (fd_ < 0) return;
  if (fstat(fd_, &info) != 0 || static_cast<std::size_t>(info.st_size) < size_) {
    throw CouplerError(fmt::format("{}: {} shrank its shared memory '{}' to {} bytes (mapped {})",
                                   self, peer, name_, info.st_size, size_));
  }
}

void SharedSegment::unlink() noexcept {
  if (owner_) {
    forget(name_);
    shm_unlink(name_.c_str());
  }
  owner_ = false;
}

}  // namespace dld::coupler
