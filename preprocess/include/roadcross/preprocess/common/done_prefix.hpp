// How long a prefix of a parallel_for's items is done, for a consumer that takes the items in
// order while the later ones are still being computed (the segment rows are written while the
// sight stage runs). The threads finish their chunks out of order; the prefix is where the first
// chunk not yet done begins. Either side can stop the other: the producer's failure wakes a
// waiting consumer, the consumer's failure makes the producer's next report throw.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>

namespace roadcross::preprocess {

class DonePrefix {
 public:
  /// What the consumer's wait throws once the producer has stopped before the end.
  struct Abandoned : std::runtime_error {
    Abandoned() : std::runtime_error("the stage computing the items stopped") {}
  };
  /// What the producer's report throws once the consumer has stopped.
  struct Stopped : std::runtime_error {
    Stopped() : std::runtime_error("the consumer of the items stopped") {}
  };

  /// Items [0, count).
  explicit DonePrefix(std::size_t count) : count_(count) {}
  DonePrefix(const DonePrefix&) = delete;
  DonePrefix& operator=(const DonePrefix&) = delete;

  std::size_t count() const noexcept { return count_; }

  // --- the producer -----------------------------------------------------------------------------
  /// Items [begin, end) are done (final: the producer writes them no more). Throws Stopped, after
  /// recording them, when the consumer has stopped, so that the producer's threads end at their
  /// next chunk.
  void done(std::size_t begin, std::size_t end);
  /// The producer ended before every item was done (an exception): the consumer's waits throw
  /// Abandoned. No effect once every item is done.
  void abandon() noexcept;

  // --- the consumer -----------------------------------------------------------------------------
  /// Waits until at least min(items, count()) items are done; returns how many are (possibly
  /// more). Throws Abandoned if the producer stops first.
  std::size_t wait_for(std::size_t items);
  /// The consumer failed: the producer's next done() throws Stopped.
  void stop() noexcept;
  bool stopped() const noexcept;

  // --- tests
  // --------------------------------------------------------------------------------------
  /// Called (on the producer's thread, before the Stopped check) by every done() with the prefix
  /// after it: lets a test make a producer thread fail, or wait, mid-stage.
  std::function<void(std::size_t prefix)> after_done_for_tests;

 private:
  const std::size_t count_;
  mutable std::mutex mutex_;
  std::condition_variable advanced_;
  std::size_t prefix_ = 0;
  /// The consumer sleeps until the prefix reaches this (it asked for a batch, not every chunk).
  std::size_t wanted_ = 0;
  /// Done ranges beyond the prefix, by their first item (at most one per producer thread).
  std::map<std::size_t, std::size_t> ahead_;
  bool abandoned_ = false;
  bool stopped_ = false;
};

}  // namespace roadcross::preprocess
