// Transparent huge pages for the build's large arrays. On the machines the build runs on (virtual
// machines) a page fault costs ~13 µs, and an array of tens of MB filled once takes one fault a
// 4 KiB page; a 2 MiB page takes one fault for 512 of them (THP here is in `madvise` mode: only
// advised memory gets them). docs/performance.md, "Build system calls and page faults (issue 27)".
#pragma once

#include <cstddef>
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

}  // namespace roadcross::preprocess
