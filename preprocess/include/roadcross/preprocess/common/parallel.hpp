// The build's one way of running work on several cores: items handed out in turn to a few
// threads, each with its own scratch state, the first exception stopping all of them.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

#include "roadcross/preprocess/common/done_prefix.hpp"

namespace roadcross::preprocess {

/// Threads the build's parallel stages use: the machine's cores, in [1, 16].
inline unsigned core_count() {
  return std::clamp(std::thread::hardware_concurrency(), 1u, 16u);
}

/// Runs job(k, state) for every k in [0, count) on at most `max_threads` threads (this one
/// included; at least 1, at most core_count()). Each thread takes the next `chunk` items (>= 1)
/// when it has finished its last ones, so uneven items balance, and owns one default-constructed
/// State for all its items (reused buffers, counters). A job may write only what belongs to its
/// own item. The first exception stops every thread at its next item and is rethrown here.
/// Returns the threads' states, for their counters. `done` (optional, of `count` items) is told
/// of every finished chunk, and abandoned at the first exception; its Stopped (the consumer
/// failed) stops the threads like a job's exception.
template <typename State, typename Job>
std::vector<State> parallel_for(std::size_t count, const Job& job, std::size_t chunk = 1,
                                unsigned max_threads = 16, DonePrefix* done = nullptr) {
  const unsigned threads = std::max(1u, std::min(core_count(), max_threads));
  chunk = std::max<std::size_t>(chunk, 1);
  std::vector<State> states(threads);
  std::vector<std::exception_ptr> errors(threads);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  const auto worker = [&](unsigned thread) {
    try {
      for (std::size_t begin; !failed && (begin = next.fetch_add(chunk)) < count;) {
        const std::size_t end = std::min(begin + chunk, count);
        for (std::size_t k = begin; k < end; ++k) job(k, states[thread]);
        if (done) done->done(begin, end);
      }
    } catch (...) {
      errors[thread] = std::current_exception();
      failed = true;
      if (done) done->abandon();
    }
  };
  std::vector<std::thread> others;
  for (unsigned t = 1; t < threads; ++t) others.emplace_back(worker, t);
  worker(0);
  for (std::thread& t : others) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return states;
}

/// No per-thread state.
struct NoState {};

}  // namespace roadcross::preprocess
