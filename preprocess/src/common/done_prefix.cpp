#include "roadcross/preprocess/common/done_prefix.hpp"

#include <algorithm>

namespace roadcross::preprocess {

void DonePrefix::done(std::size_t begin, std::size_t end) {
  std::size_t prefix;
  {
    const std::lock_guard lock(mutex_);
    if (begin == prefix_) {
      prefix_ = end;
      for (auto next = ahead_.begin(); next != ahead_.end() && next->first == prefix_;) {
        prefix_ = next->second;
        next = ahead_.erase(next);
      }
      // Only when the consumer's batch is complete: waking it for every chunk would cost a
      // context switch per chunk for nothing.
      if (prefix_ >= wanted_) advanced_.notify_all();
    } else {
      ahead_.emplace(begin, end);
    }
    prefix = prefix_;
  }
  if (after_done_for_tests) after_done_for_tests(prefix);
  if (this->stopped()) throw Stopped();
}

void DonePrefix::abandon() noexcept {
  const std::lock_guard lock(mutex_);
  if (prefix_ >= count_) return;
  abandoned_ = true;
  advanced_.notify_all();
}

std::size_t DonePrefix::wait_for(std::size_t items) {
  std::unique_lock lock(mutex_);
  wanted_ = std::min(items, count_);
  advanced_.wait(lock, [&] { return prefix_ >= wanted_ || abandoned_; });
  if (prefix_ < wanted_) throw Abandoned();
  return prefix_;
}

void DonePrefix::stop() noexcept {
  const std::lock_guard lock(mutex_);
  stopped_ = true;
}

bool DonePrefix::stopped() const noexcept {
  const std::lock_guard lock(mutex_);
  return stopped_;
}

}  // namespace roadcross::preprocess
