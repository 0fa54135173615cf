// Membership in a sorted list of OSM ids for ids asked mostly in ascending order: the nodes of a
// sorted file, asked one by one whether the build wants them.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace roadcross::preprocess {

/// std::binary_search over `sorted` (ascending; duplicates allowed), answered from where the
/// previous question's search ended: a larger id gallops forward from there (a few comparisons
/// when the ids come in order, as a sorted file's nodes do: millions of nodes, most of them not
/// wanted, each a binary search over the whole list cost ~23 ns at 50x tiled Monaco), a smaller
/// one is searched below it. The same answers in any order of questions.
class SortedIdCursor {
 public:
  /// `sorted` must outlive the cursor and stay unchanged.
  explicit SortedIdCursor(const std::vector<std::int64_t>& sorted) : ids_(sorted) {}

  bool contains(std::int64_t id) {
    const std::size_t n = ids_.size();
    // Invariant: every id before at_ is below the previous question's id.
    std::size_t lo = 0, hi = at_;
    if (at_ == 0 || ids_[at_ - 1] < id) {
      // Every id before at_ is below this one too: gallop from at_ to an id not below it.
      lo = at_, hi = at_;
      for (std::size_t step = 1; hi < n && ids_[hi] < id; step *= 2) {
        lo = hi + 1;
        hi = std::min(n, hi + step);
      }
    }
    const auto begin = ids_.begin();
    at_ = static_cast<std::size_t>(std::lower_bound(begin + static_cast<std::ptrdiff_t>(lo),
                                                    begin + static_cast<std::ptrdiff_t>(hi), id) -
                                   begin);
    return at_ < n && ids_[at_] == id;
  }

 private:
  const std::vector<std::int64_t>& ids_;
  std::size_t at_ = 0;  ///< where the last search ended: the first id not below the last one asked
};

}  // namespace roadcross::preprocess
