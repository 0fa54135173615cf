#pragma once
// Large arrays first written in one go (the obstacles' tables between the OSM passes): backed
// by 2 MiB pages where Linux can, so that their first touch takes one page fault a 2 MiB
// instead of one a 4 KiB (in the build's VM a fault cost ~10 us: the faults of ~45 MB were
// most of the time between the passes).
#include <cstddef>
#include <cstdint>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace roadcross::preprocess {

/// Advises huge pages for the whole 2 MiB pages inside [data, data + bytes); call it before the
/// first write. Only a hint: without transparent huge pages (or off Linux) nothing changes.
inline void advise_huge_pages(void* data, std::size_t bytes) noexcept {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + kHugePage - 1) & ~(kHugePage - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(kHugePage - 1);
  if (end > begin) ::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
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

}  // namespace roadcross::preprocess
