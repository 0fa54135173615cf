// Transparent huge pages for the build's large arrays. On the machines the build runs on (virtual
// machines) a page fault costs ~10-13 µs, and an array of tens of MB filled once takes one fault a
// 4 KiB page; a 2 MiB page takes one fault for 512 of them (THP here is in `madvise` mode: only
// advised memory gets them). docs/performance-log.md,
// "Build system calls and page faults (issue 27)".
#pragma once

#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace roadcross::preprocess {

/// Advises huge pages for the 2 MiB-aligned part of [data, data + bytes), if there is one; a
/// hint only (nothing happens where the kernel cannot or will not). Call it before the memory is
/// first written: pages already faulted in stay small until the kernel collapses them.
void advise_huge_pages(const void* data, std::size_t bytes) noexcept;

/// The same for a vector's reserved capacity.
template <typename T, typename Allocator>
void advise_huge_pages(const std::vector<T, Allocator>& reserved) noexcept {
  advise_huge_pages(reserved.data(), reserved.capacity() * sizeof(T));
}

/// items.reserve(n), the new storage (when there is one) advised huge pages before the items
/// are copied into it.
template <typename T, typename Allocator>
void reserve_on_huge_pages(std::vector<T, Allocator>& items, std::size_t n) {
  if (n <= items.capacity()) return;
  std::vector<T, Allocator> fresh;
  fresh.reserve(n);
  advise_huge_pages(fresh.data(), n * sizeof(T));
  fresh.assign(items.begin(), items.end());
  items.swap(fresh);
}

/// items.resize(n) on storage advised huge pages when it is newly allocated.
template <typename T, typename Allocator>
void resize_on_huge_pages(std::vector<T, Allocator>& items, std::size_t n) {
  reserve_on_huge_pages(items, n);
  items.resize(n);
}

/// Faults in the whole 4 KiB pages of [data, data + bytes) on a thread of its own, front to
/// back, while the caller's thread fills them (madvise MADV_POPULATE_WRITE): the kernel's
/// zeroing of fresh pages, most of what a first write of a large array costs, runs on the other
/// core. The contents are not touched (a page already present is left as it is), so the filling
/// thread needs no care. Only where a second core would otherwise idle. The destructor stops it
/// at its next 8 MiB and waits; nothing happens where the kernel lacks the advice.
class PrefaultBeside {
 public:
  PrefaultBeside(const void* data, std::size_t bytes);
  ~PrefaultBeside();
  PrefaultBeside(const PrefaultBeside&) = delete;
  PrefaultBeside& operator=(const PrefaultBeside&) = delete;

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace roadcross::preprocess
