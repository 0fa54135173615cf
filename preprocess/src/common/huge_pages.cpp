#include "roadcross/preprocess/common/huge_pages.hpp"

#include <algorithm>
#include <cstdint>
#include <system_error>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace roadcross::preprocess {

void advise_huge_pages(const void* data, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePageBytes = std::uintptr_t{2} << 20;
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (start + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  const std::uintptr_t last = (start + bytes) & ~(kHugePageBytes - 1);
  // Only whole 2 MiB pages inside the array: the advice applies to the mapping's pages, and a
  // neighbour's memory must not become huge (and resident) through this array.
  if (last > first) {
    (void)::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

PrefaultBeside::PrefaultBeside(const void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::uintptr_t kPageBytes = 4096, kStepBytes = std::uintptr_t{8} << 20;
  const auto start = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (start + kPageBytes - 1) & ~(kPageBytes - 1);
  const std::uintptr_t last = (start + bytes) & ~(kPageBytes - 1);
  if (last <= first) return;
  try {
    thread_ = std::thread([this, first, last] {
      for (std::uintptr_t at = first; at < last && !stop_; at += kStepBytes) {
        const std::uintptr_t end = std::min(last, at + kStepBytes);
        // Fails (EINVAL) on kernels before 5.14: then nothing more is tried.
        if (::madvise(reinterpret_cast<void*>(at), end - at, MADV_POPULATE_WRITE) != 0) return;
      }
    });
  } catch (const std::system_error&) {
    // No thread: the filling thread faults its pages itself, as without this.
  }
#else
  (void)data;
  (void)bytes;
#endif
}

PrefaultBeside::~PrefaultBeside() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

}  // namespace roadcross::preprocess
