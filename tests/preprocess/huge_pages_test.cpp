#include "roadcross/preprocess/common/huge_pages.hpp"

#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rp = roadcross::preprocess;

namespace {

/// Pages of [data, data + bytes) resident (mincore), of all whole pages there.
std::size_t resident_pages(const void* data, std::size_t bytes) {
  const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
  std::vector<unsigned char> in_core((bytes + page - 1) / page);
  if (::mincore(const_cast<void*>(data), bytes, in_core.data()) != 0) return 0;
  std::size_t resident = 0;
  for (unsigned char c : in_core) resident += c & 1;
  return resident;
}

}  // namespace

// The thread filling the memory and the one faulting it in ahead of it: every byte written is
// read back (the prefault does not write), and when the kernel has MADV_POPULATE_WRITE every
// page is resident afterwards, also those the filling thread did not reach.
TEST(PrefaultBeside, FaultsInWithoutTouchingWhatTheFillingThreadWrites) {
  constexpr std::size_t kBytes = std::size_t{48} << 20;
  void* memory =
      ::mmap(nullptr, kBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(memory, MAP_FAILED);
  auto* bytes = static_cast<std::uint8_t*>(memory);
  EXPECT_EQ(resident_pages(memory, kBytes), 0u);
  {
    const rp::PrefaultBeside ahead(memory, kBytes);
    for (std::size_t i = 0; i < kBytes / 2; ++i) bytes[i] = static_cast<std::uint8_t>(i * 7 + 1);
    // The destructor stops the thread at its next step: wait for it to get through (5 s at
    // most; a kernel without the advice faults in nothing).
    for (int waited = 0; waited < 5000 && resident_pages(memory, kBytes) < kBytes / 4096;
         ++waited) {
      ::usleep(1000);
    }
  }
  bool same = true;
  for (std::size_t i = 0; i < kBytes / 2; ++i) {
    same = same && bytes[i] == static_cast<std::uint8_t>(i * 7 + 1);
  }
  EXPECT_TRUE(same);
  if (::madvise(memory, 4096, MADV_POPULATE_WRITE) == 0) {  // the kernel has the advice
    EXPECT_EQ(resident_pages(memory, kBytes), kBytes / 4096);
  }
  // (read only now: reading maps untouched pages to the zero page, which counts as resident)
  for (std::size_t i = kBytes / 2; i < kBytes; i += 4096) ASSERT_EQ(bytes[i], 0u);
  ::munmap(memory, kBytes);
}

// Nothing to do (an empty or sub-page range) is no thread and no error.
TEST(PrefaultBeside, AnEmptyRangeIsNothing) {
  std::vector<std::uint8_t> small(100, 3);
  { const rp::PrefaultBeside nothing(small.data(), 0); }
  { const rp::PrefaultBeside within_a_page(small.data(), small.size()); }
  for (std::uint8_t b : small) ASSERT_EQ(b, 3);
}
