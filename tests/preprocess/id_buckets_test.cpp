#include "roadcross/preprocess/common/id_buckets.hpp"
#include "roadcross/preprocess/sight/obstacle_edge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace rp = roadcross::preprocess;

namespace {

struct Item {
  std::int64_t id = 0;
  std::uint32_t index = 0;  // position in the ids: tells the items of one id apart
};

/// Sorts `ids` with sort_into_id_buckets and checks the table against std::sort of (id, index)
/// pairs, and every bucket against its definition.
void expect_sorted_like_std_sort(const std::vector<std::int64_t>& ids, int max_bucket_bits) {
  std::vector<Item> table;
  std::size_t calls = 0;
  bool in_order = true;
  const rp::IdBuckets buckets = rp::sort_into_id_buckets(
      ids,
      [&](std::size_t i) {
        in_order = in_order && i == calls;
        ++calls;
        return Item{ids[i], static_cast<std::uint32_t>(i)};
      },
      [](const Item& x) { return x.id; }, table, max_bucket_bits);
  EXPECT_EQ(calls, ids.size());
  EXPECT_TRUE(in_order);
  ASSERT_EQ(table.size(), ids.size());

  std::vector<std::pair<std::int64_t, std::uint32_t>> want, got;
  for (std::size_t i = 0; i < ids.size(); ++i) want.emplace_back(ids[i], i);
  std::sort(want.begin(), want.end());
  for (const Item& x : table) got.emplace_back(x.id, x.index);
  // The ids in the same order as std::sort's, ...
  for (std::size_t i = 0; i < ids.size(); ++i) ASSERT_EQ(got[i].first, want[i].first) << i;
  // ... and the same items (those of one id in any order).
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, want);

  if (ids.empty()) {
    EXPECT_TRUE(buckets.empty());
    return;
  }
  const std::int64_t lo = want.front().first, hi = want.back().first;
  EXPECT_EQ(buckets.min_id, lo);
  EXPECT_EQ(buckets.max_id, hi);
  ASSERT_LE(buckets.begins.size(), (std::size_t{1} << max_bucket_bits) + 1);
  EXPECT_EQ(buckets.begins.front(), 0u);
  EXPECT_EQ(buckets.begins.back(), ids.size());
  for (std::size_t b = 0; b + 1 < buckets.begins.size(); ++b) {
    ASSERT_LE(buckets.begins[b], buckets.begins[b + 1]);
    for (std::size_t i = buckets.begins[b]; i < buckets.begins[b + 1]; ++i) {
      const std::uint64_t offset =
          static_cast<std::uint64_t>(table[i].id) - static_cast<std::uint64_t>(lo);
      ASSERT_EQ(offset >> buckets.shift, b) << "item " << i;
    }
  }
  // Every id's bucket holds all its items; ids outside the range have none.
  for (const std::int64_t id : ids) {
    const auto [first, last] = buckets.range_of(id);
    const auto n = std::count_if(table.begin() + static_cast<std::ptrdiff_t>(first),
                                 table.begin() + static_cast<std::ptrdiff_t>(last),
                                 [&](const Item& x) { return x.id == id; });
    EXPECT_EQ(n, std::count(ids.begin(), ids.end(), id));
  }
  if (lo > std::numeric_limits<std::int64_t>::min()) {
    EXPECT_EQ(buckets.range_of(lo - 1), std::make_pair(std::size_t{0}, std::size_t{0}));
  }
  if (hi < std::numeric_limits<std::int64_t>::max()) {
    EXPECT_EQ(buckets.range_of(hi + 1), std::make_pair(std::size_t{0}, std::size_t{0}));
  }
}

}  // namespace

TEST(IdBuckets, EmptyAndSingle) {
  expect_sorted_like_std_sort({}, 20);
  expect_sorted_like_std_sort({42}, 20);
  expect_sorted_like_std_sort({-7, -7, -7}, 20);
}

TEST(IdBuckets, RandomIdsWithRepeatsLikeStdSort) {
  std::mt19937_64 random(27);
  for (const std::int64_t span : {std::int64_t{50}, std::int64_t{1} << 20, std::int64_t{1} << 34,
                                  std::int64_t{12'000'000'000}}) {
    for (const int bits : {1, 4, 20}) {
      std::vector<std::int64_t> ids;
      std::uniform_int_distribution<std::int64_t> id(1, span);
      for (int i = 0; i < 5000; ++i) {
        ids.push_back(id(random));
        if (i % 7 == 0) ids.push_back(ids[random() % ids.size()]);  // a node in several ways
      }
      expect_sorted_like_std_sort(ids, bits);
    }
  }
}

TEST(IdBuckets, RunsOfConsecutiveIdsAndClusters) {
  // OSM-like: buildings' nodes in runs of consecutive ids, in a few far apart clusters (tiled
  // copies of one extract), and negative ids (an editor's new objects).
  std::vector<std::int64_t> ids;
  for (const std::int64_t base : {std::int64_t{9'000'000'000}, std::int64_t{3}, std::int64_t{-500},
                                  std::int64_t{4'294'967'290}}) {
    for (std::int64_t way = 0; way < 200; ++way) {
      for (std::int64_t k = 0; k < 5; ++k) ids.push_back(base + 7 * (199 - way) + k);
      ids.push_back(base + 7 * (199 - way));  // closed ring
    }
  }
  expect_sorted_like_std_sort(ids, 20);
  expect_sorted_like_std_sort(ids, 3);
}

/// An item with no default member initialisers, for a table whose pages are not written before
/// the items are placed (the obstacles' node table).
struct BareItem {
  std::int64_t id;
  std::uint32_t index;
};

TEST(IdBuckets, ManyBucketsSortedOnEveryCoreIntoAnUninitialisedTable) {
  // 2^16 buckets of ~6 items each: the buckets are sorted in 16 blocks, shared by the threads.
  std::mt19937_64 random(4);
  std::vector<std::int64_t> ids;
  std::uniform_int_distribution<std::int64_t> id(1'000'000, 1'000'000 + (std::int64_t{1} << 22));
  for (int i = 0; i < 400'000; ++i) {
    ids.push_back(id(random));
    if (i % 5 == 0) ids.push_back(ids[random() % ids.size()]);
  }
  std::vector<BareItem, rp::UninitialisedAllocator<BareItem>> table;
  const rp::IdBuckets buckets = rp::sort_into_id_buckets(
      ids,
      [&](std::size_t i) {
        return BareItem{ids[i], static_cast<std::uint32_t>(i)};
      },
      [](const BareItem& x) { return x.id; }, table, 16);
  ASSERT_EQ(buckets.begins.size(), (std::size_t{1} << 16) + 1);
  std::vector<std::pair<std::int64_t, std::uint32_t>> want, got;
  for (std::size_t i = 0; i < ids.size(); ++i) want.emplace_back(ids[i], i);
  std::sort(want.begin(), want.end());
  for (const BareItem& x : table) got.emplace_back(x.id, x.index);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i].first, want[i].first) << i;
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, want);
  // The same table again (each bucket sorted by one std::sort of the same items, whichever
  // thread took it): item for item, those of one id too.
  std::vector<BareItem, rp::UninitialisedAllocator<BareItem>> again;
  rp::sort_into_id_buckets(
      ids,
      [&](std::size_t i) {
        return BareItem{ids[i], static_cast<std::uint32_t>(i)};
      },
      [](const BareItem& x) { return x.id; }, again, 16);
  ASSERT_EQ(again.size(), table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    ASSERT_EQ(again[i].index, table[i].index) << i;
  }
}

TEST(IdBuckets, TheWholeSigned64BitRange) {
  const std::int64_t lo = std::numeric_limits<std::int64_t>::min();
  const std::int64_t hi = std::numeric_limits<std::int64_t>::max();
  expect_sorted_like_std_sort({hi, 0, lo, -1, 1, hi, lo, hi - 1, lo + 1}, 20);
  expect_sorted_like_std_sort({hi, lo}, 1);
}

TEST(HugePages, ReserveAndResizeKeepTheItems) {
  // Large enough for whole 2 MiB pages inside the storage (the advice is only a hint: the
  // contents must be the same either way).
  std::vector<std::int64_t> items = {5, -3, 7};
  rp::reserve_on_huge_pages(items, std::size_t{1} << 20);
  EXPECT_GE(items.capacity(), std::size_t{1} << 20);
  EXPECT_EQ(items, (std::vector<std::int64_t>{5, -3, 7}));
  rp::resize_on_huge_pages(items, std::size_t{3} << 20);
  ASSERT_EQ(items.size(), std::size_t{3} << 20);
  EXPECT_EQ(items[0], 5);
  EXPECT_EQ(items[1], -3);
  EXPECT_EQ(items[2], 7);
  EXPECT_EQ(std::count(items.begin() + 3, items.end(), 0), (std::int64_t{3} << 20) - 3);
  rp::resize_on_huge_pages(items, 2);  // shrinking keeps the storage
  EXPECT_EQ(items, (std::vector<std::int64_t>{5, -3}));
}
