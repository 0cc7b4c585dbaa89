// Memory mapped from the system for itself, returned to it when freed.
#pragma once

#include <cstddef>
#include <new>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <utility>

namespace mbao {

// Its pages are mapped on first touch, so room that is never written costs
// nothing. For large, short-lived blocks: malloc keeps some of those in its
// heaps once freed (its mmap threshold grows with the blocks it frees).
class PageBlock {
 public:
  PageBlock() = default;
  explicit PageBlock(std::size_t bytes) : bytes_(bytes) {
    if (bytes_ == 0) return;
    data_ = mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (data_ == MAP_FAILED) {
      data_ = nullptr;
      throw std::bad_alloc();
    }
#ifdef MADV_HUGEPAGE
    madvise(data_, bytes_, MADV_HUGEPAGE);
#endif
  }
  PageBlock(PageBlock&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)), bytes_(std::exchange(other.bytes_, 0)) {}
  PageBlock& operator=(PageBlock&& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(bytes_, other.bytes_);
    return *this;
  }
  PageBlock(const PageBlock&) = delete;
  PageBlock& operator=(const PageBlock&) = delete;
  ~PageBlock() {
    if (data_) munmap(data_, bytes_);
  }

  void* data() const { return data_; }

  // Hands back the whole pages of the first `bytes`, which read as zeros after.
  void release_before(std::size_t bytes) {
    const auto page = std::size_t(sysconf(_SC_PAGESIZE));
    const std::size_t whole = std::min(bytes, bytes_) / page * page;
    if (whole) madvise(data_, whole, MADV_DONTNEED);
  }

 private:
  void* data_ = nullptr;
  std::size_t bytes_ = 0;
};

}  // namespace mbao
