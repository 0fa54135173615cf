// lower_bound_near against std::lower_bound from every hint, and SortedIdCursor against
// std::binary_search: the same answers for ids asked in ascending order (a sorted file), in
// descending order, at random, repeated, and for lists with duplicates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "roadcross/preprocess/common/sorted_id_cursor.hpp"

namespace rp = roadcross::preprocess;

namespace {

void expect_binary_search_answers(const std::vector<std::int64_t>& sorted,
                                  const std::vector<std::int64_t>& questions) {
  rp::SortedIdCursor cursor(sorted);
  for (std::size_t i = 0; i < questions.size(); ++i) {
    ASSERT_EQ(cursor.contains(questions[i]),
              std::binary_search(sorted.begin(), sorted.end(), questions[i]))
        << "question " << i << ": id " << questions[i];
  }
}

TEST(LowerBoundNear, SameAnswerAsLowerBoundFromEveryHint) {
  std::mt19937_64 random(4);
  for (const std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{3},
                                 std::size_t{8}, std::size_t{33}, std::size_t{300}}) {
    std::vector<std::int64_t> sorted(size);
    for (std::int64_t& id : sorted) id = static_cast<std::int64_t>(random() % 200) - 50;
    std::sort(sorted.begin(), sorted.end());
    for (std::int64_t id = -60; id <= 160; ++id) {
      const auto expected = std::lower_bound(sorted.begin(), sorted.end(), id);
      for (auto hint = sorted.begin();; ++hint) {
        ASSERT_EQ(rp::lower_bound_near(sorted.begin(), sorted.end(), hint, id,
                                       [](std::int64_t x) { return x; }),
                  expected)
            << "size " << size << ", id " << id << ", hint " << (hint - sorted.begin());
        if (hint == sorted.end()) break;
      }
    }
  }
}

TEST(SortedIdCursor, HandMadeList) {
  const std::vector<std::int64_t> ids{-5, 2, 3, 3, 10, 40};
  rp::SortedIdCursor cursor(ids);
  // In order, with gaps, then back and forth.
  EXPECT_FALSE(cursor.contains(-7));
  EXPECT_TRUE(cursor.contains(-5));
  EXPECT_FALSE(cursor.contains(1));
  EXPECT_TRUE(cursor.contains(3));
  EXPECT_TRUE(cursor.contains(3));
  EXPECT_FALSE(cursor.contains(39));
  EXPECT_TRUE(cursor.contains(40));
  EXPECT_FALSE(cursor.contains(41));
  EXPECT_TRUE(cursor.contains(2));
  EXPECT_FALSE(cursor.contains(11));
  EXPECT_TRUE(cursor.contains(10));
  EXPECT_TRUE(cursor.contains(-5));
  const std::vector<std::int64_t> none;
  rp::SortedIdCursor nothing(none);
  EXPECT_FALSE(nothing.contains(0));
  EXPECT_FALSE(nothing.contains(-1));
}

TEST(SortedIdCursor, SameAnswersAsBinarySearchInEveryOrder) {
  std::mt19937_64 random(27);
  for (const std::size_t size :
       {std::size_t{1}, std::size_t{2}, std::size_t{17}, std::size_t{5000}}) {
    std::vector<std::int64_t> sorted(size);
    for (std::int64_t& id : sorted) id = static_cast<std::int64_t>(random() % 20000) - 500;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::int64_t> ascending(30000);
    for (std::size_t i = 0; i < ascending.size(); ++i) ascending[i] = std::int64_t(i) - 2000;
    expect_binary_search_answers(sorted, ascending);  // every id, as a sorted file's nodes
    std::vector<std::int64_t> descending(ascending.rbegin(), ascending.rend());
    expect_binary_search_answers(sorted, descending);
    std::vector<std::int64_t> shuffled = ascending;
    std::shuffle(shuffled.begin(), shuffled.end(), random);
    expect_binary_search_answers(sorted, shuffled);
    // Mostly ascending with jumps back (files merged or out of order) and repeats.
    std::vector<std::int64_t> mostly;
    for (std::int64_t id = -600; id < 21000; id += 1 + std::int64_t(random() % 7)) {
      mostly.push_back(id);
      if (random() % 50 == 0) mostly.push_back(id - std::int64_t(random() % 3000));
      if (random() % 20 == 0) mostly.push_back(id);
    }
    expect_binary_search_answers(sorted, mostly);
  }
}

}  // namespace
