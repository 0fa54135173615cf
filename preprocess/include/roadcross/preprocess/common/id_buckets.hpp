#pragma once
// A table of items sorted by OSM id, made by counting the ids into buckets of the id range and
// sorting each (small) bucket: one sequential pass to count and one to place, no second copy
// of the table (a comparison sort of millions of 12-byte items was a tenth of the ways pass, and
// a radix sort would need a second table the size of the first). The buckets stay as the
// table's index: a look-up searches one bucket.
#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include "roadcross/preprocess/common/huge_pages.hpp"
#include "roadcross/preprocess/common/parallel.hpp"

namespace roadcross::preprocess {

/// Bucket b holds the items whose id is in [min_id + (b << shift), min_id + ((b + 1) << shift)):
/// table positions [begins[b], begins[b + 1]). Empty when there is no item.
struct IdBuckets {
  std::int64_t min_id = 0, max_id = -1;
  int shift = 0;
  std::vector<std::uint32_t> begins;  ///< one per bucket, and the table's size last

  bool empty() const { return begins.empty(); }
  /// The positions [first, last) of the bucket that would hold `id`; {0, 0} when no bucket does.
  std::pair<std::size_t, std::size_t> range_of(std::int64_t id) const {
    if (begins.empty() || id < min_id || id > max_id) return {0, 0};
    const auto b = static_cast<std::size_t>(static_cast<std::uint64_t>(id) -
                                            static_cast<std::uint64_t>(min_id)) >>
                   shift;
    return {begins[b], begins[b + 1]};
  }
};

/// Fills `table` (a std::vector, or one with another allocator) with make_item(i) for every i of
/// `ids` (called once each, i = 0, 1, ... in order, so the items may follow a running state),
/// sorted by id (`id_of(item)` must be ids[i]; items of one id in no particular order), and returns
/// its buckets: at most 2^max_bucket_bits of them plus one (4 bytes each), the fewest bits that
/// make the id range fit. At most 2^32 - 1 items.
template <typename Table, typename MakeItem, typename IdOf>
IdBuckets sort_into_id_buckets(const std::vector<std::int64_t>& ids, MakeItem&& make_item,
                               IdOf&& id_of, Table& table, int max_bucket_bits = 20) {
  using T = typename Table::value_type;
  IdBuckets out;
  table.clear();
  if (ids.empty()) return out;
  if (ids.size() >= std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("sort_into_id_buckets: more than 2^32 - 1 ids");
  }
  // The table's pages are faulted in on another core while this one counts and then places
  // the items (at country scale hundreds of MiB, whose first writes are mostly the kernel's
  // zeroing); a table of trivially constructible items is not written before.
  resize_on_huge_pages(table, ids.size());
  std::optional<PrefaultBeside> prefault(std::in_place, table.data(), ids.size() * sizeof(T));
  const auto [min_it, max_it] = std::minmax_element(ids.begin(), ids.end());
  out.min_id = *min_it;
  out.max_id = *max_it;
  // Unsigned: the range of two signed 64-bit ids always fits.
  const std::uint64_t range =
      static_cast<std::uint64_t>(out.max_id) - static_cast<std::uint64_t>(out.min_id);
  out.shift = std::max(0, static_cast<int>(std::bit_width(range)) - max_bucket_bits);
  const std::size_t buckets = static_cast<std::size_t>(range >> out.shift) + 1;
  const auto bucket_of = [&](std::int64_t id) {
    return static_cast<std::size_t>(
        (static_cast<std::uint64_t>(id) - static_cast<std::uint64_t>(out.min_id)) >> out.shift);
  };
  // Counts at begins[b + 1], then their running sums: begins[b] is where bucket b starts.
  out.begins.assign(buckets + 1, 0);
  for (const std::int64_t id : ids) ++out.begins[bucket_of(id) + 1];
  for (std::size_t b = 1; b <= buckets; ++b) out.begins[b] += out.begins[b - 1];
  // Placed through a cursor per bucket: begins[b] itself, advanced to where bucket b + 1
  // begins, so that a shift by one afterwards restores the starts (no second array).
  for (std::size_t i = 0; i < ids.size(); ++i)
    table[out.begins[bucket_of(ids[i])]++] = make_item(i);
  prefault.reset();
  for (std::size_t b = buckets; b > 0; --b) out.begins[b] = out.begins[b - 1];
  out.begins[0] = 0;
  // The buckets are sorted on every core, in blocks of consecutive buckets (the node pass's
  // decoders wait while the obstacles' table is made): each bucket by one std::sort of the same
  // items, whichever thread takes it, so the table is the same for every number of threads.
  const auto by_id = [&](const T& x, const T& y) { return id_of(x) < id_of(y); };
  constexpr std::size_t kBucketsABlock = 4096;
  parallel_for<NoState>((buckets + kBucketsABlock - 1) / kBucketsABlock,
                        [&](std::size_t block, NoState&) {
                          const std::size_t end = std::min(buckets, (block + 1) * kBucketsABlock);
                          for (std::size_t b = block * kBucketsABlock; b < end; ++b) {
                            if (out.begins[b + 1] - out.begins[b] > 1) {
                              std::sort(table.begin() + out.begins[b],
                                        table.begin() + out.begins[b + 1], by_id);
                            }
                          }
                        },
                        4);
  return out;
}

}  // namespace roadcross::preprocess
