// The segment rows are written while the sight stage runs (issue 27): DonePrefix hands the
// finished prefix of parallel_for's items to a consumer, and either side's failure stops the
// other. Here on parallel_for alone, then on whole builds of Monaco whose writer or sight thread
// is made to fail mid-stage (BuildOptions::test_hooks): the build fails with that error, promptly
// (no wait for a prefix that never completes), and leaves no file.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/done_prefix.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/parallel.hpp"

namespace rp = roadcross::preprocess;
using roadcross::testing::TempDir;
using namespace std::chrono_literals;

namespace {

TEST(DonePrefix, AdvancesOverChunksDoneOutOfOrder) {
  rp::DonePrefix prefix(10);
  prefix.done(4, 6);
  prefix.done(8, 10);
  EXPECT_EQ(prefix.wait_for(0), 0u);
  prefix.done(0, 4);
  EXPECT_EQ(prefix.wait_for(4), 6u);
  prefix.done(6, 8);
  EXPECT_EQ(prefix.wait_for(100), 10u);  // capped at the count
}

TEST(DonePrefix, ParallelForPublishesEveryItemInOrder) {
  constexpr std::size_t kCount = 100000;
  rp::DonePrefix prefix(kCount);
  std::vector<std::atomic<int>> items(kCount);
  std::atomic<bool> consumer_saw_unfinished{false};
  auto consumer = std::async(std::launch::async, [&] {
    for (std::size_t have = 0; have < kCount;) {
      const std::size_t now = prefix.wait_for(have + 1000);
      for (std::size_t i = have; i < now; ++i) {
        if (items[i].load() != 1) consumer_saw_unfinished = true;
      }
      have = now;
    }
  });
  rp::parallel_for<rp::NoState>(
      kCount, [&](std::size_t i, rp::NoState&) { items[i] = 1; }, 64, 16, &prefix);
  ASSERT_EQ(consumer.wait_for(30s), std::future_status::ready);
  consumer.get();
  EXPECT_FALSE(consumer_saw_unfinished);
}

TEST(DonePrefix, ProducerExceptionWakesTheWaitingConsumer) {
  rp::DonePrefix prefix(1000);
  auto consumer = std::async(std::launch::async, [&] { return prefix.wait_for(1000); });
  EXPECT_THROW(rp::parallel_for<rp::NoState>(
                   1000,
                   [](std::size_t i, rp::NoState&) {
                     if (i == 500) throw std::runtime_error("item 500");
                   },
                   8, 16, &prefix),
               std::runtime_error);
  ASSERT_EQ(consumer.wait_for(10s), std::future_status::ready) << "the consumer still waits";
  EXPECT_THROW(consumer.get(), rp::DonePrefix::Abandoned);
}

TEST(DonePrefix, ConsumerStopEndsTheProducerAtItsNextChunk) {
  constexpr std::size_t kCount = 1000000;
  rp::DonePrefix prefix(kCount);
  std::atomic<std::size_t> items_done{0};
  auto consumer = std::async(std::launch::async, [&] {
    prefix.wait_for(1000);
    prefix.stop();
    return items_done.load();
  });
  EXPECT_THROW(rp::parallel_for<rp::NoState>(
                   kCount,
                   [&](std::size_t, rp::NoState&) {
                     ++items_done;
                     std::this_thread::sleep_for(1us);
                   },
                   64, 16, &prefix),
               rp::DonePrefix::Stopped);
  const std::size_t at_stop = consumer.get();
  // Every thread finishes the chunk it holds, then stops.
  EXPECT_LE(items_done.load(), at_stop + 64 * rp::core_count());
  EXPECT_LT(items_done.load(), kCount);
}

/// A Monaco build (37 000 segments) with small row batches: the writer writes during the sight
/// stage. Runs `options` on a thread; fails the test (and ends the process: the build would hold
/// its references) if it is not over within 120 s.
std::exception_ptr build_within_time_limit(const rp::BuildOptions& options) {
  auto done = std::make_shared<std::promise<std::exception_ptr>>();
  std::future<std::exception_ptr> result = done->get_future();
  std::thread([options, done] {
    try {
      rp::run_build(options);
      done->set_value(nullptr);
    } catch (...) {
      done->set_value(std::current_exception());
    }
  }).detach();
  if (result.wait_for(120s) != std::future_status::ready) {
    ADD_FAILURE() << "the build did not end within 120 s (a thread waits for the other)";
    std::_Exit(1);
  }
  return result.get();
}

rp::BuildOptions monaco_options(const TempDir& dir) {
  rp::BuildOptions options;
  options.osm_path = std::string(ROADCROSS_MAPS_DIR) + "/monaco/monaco.osm.pbf";
  options.output_path = dir.file("monaco.gpkg");
  options.test_hooks.row_batch = 256;
  return options;
}

/// What the build left in `dir`.
std::vector<std::string> files_in(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    names.push_back(entry.path().filename().string());
  }
  return names;
}

TEST(SegmentRowsDuringSight, WriterFailureStopsTheSightStage) {
  TempDir dir;
  rp::BuildOptions options = monaco_options(dir);
  std::atomic<bool> writer_failed{false};
  std::atomic<bool> waited_too_long{false};
  std::atomic<int> chunks_after_failure{0};
  std::atomic<std::size_t> final_at_end{0};
  // The third batch fails, as a full disk would.
  options.test_hooks.before_row_batch = [&](std::size_t begin, std::size_t) {
    if (begin < 512) return;
    writer_failed = true;
    throw rp::OutputError("injected write failure");
  };
  // The sight threads wait, beyond the writer's batches, for its failure: the stage cannot end
  // before it. Then they give its thread 200 ms to stop the stage (it may be descheduled between
  // its failure and the stop).
  std::atomic<bool> stop_seen{false};
  options.test_hooks.after_sight_chunk = [&](std::size_t final_segments) {
    if (stop_seen) ++chunks_after_failure;
    final_at_end = std::max(final_at_end.load(), final_segments);
    if (final_segments < 2048) return;
    const auto start = std::chrono::steady_clock::now();
    while (!writer_failed) {
      if (std::chrono::steady_clock::now() - start > 30s) {
        waited_too_long = true;
        return;
      }
      std::this_thread::sleep_for(1ms);
    }
    std::this_thread::sleep_for(200ms);
    stop_seen = true;
  };
  const std::exception_ptr error = build_within_time_limit(options);
  ASSERT_TRUE(error) << "the build succeeded";
  try {
    std::rethrow_exception(error);
  } catch (const rp::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("injected write failure"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(options.output_path), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not the writer's error: " << e.what();
  }
  EXPECT_FALSE(waited_too_long);
  // Each sight thread reports at most the chunk it held when the writer failed, then stops.
  EXPECT_LE(chunks_after_failure.load(), static_cast<int>(rp::core_count()));
  EXPECT_LT(final_at_end.load(), 4096u) << "the sight stage went on after the writer failed";
  EXPECT_TRUE(files_in(dir).empty()) << "left: " << files_in(dir).front();
}

TEST(SegmentRowsDuringSight, SightFailureStopsTheWriter) {
  TempDir dir;
  rp::BuildOptions options = monaco_options(dir);
  std::atomic<std::size_t> rows_begun{0};
  std::atomic<bool> waited_too_long{false};
  std::atomic<bool> sight_failed{false};
  std::atomic<int> batches_after_failure{0};
  options.test_hooks.before_row_batch = [&](std::size_t begin, std::size_t) {
    if (sight_failed) ++batches_after_failure;
    rows_begun = begin;
  };
  // A sight thread fails once the writer has written a few batches.
  options.test_hooks.after_sight_chunk = [&](std::size_t final_segments) {
    if (final_segments < 2048) return;
    const auto start = std::chrono::steady_clock::now();
    while (rows_begun < 1024) {
      if (std::chrono::steady_clock::now() - start > 30s) {
        waited_too_long = true;
        break;
      }
      std::this_thread::sleep_for(1ms);
    }
    sight_failed = true;
    throw std::runtime_error("injected sight failure");
  };
  const std::exception_ptr error = build_within_time_limit(options);
  ASSERT_TRUE(error) << "the build succeeded";
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    EXPECT_EQ(std::string(e.what()), "injected sight failure");
  }
  EXPECT_FALSE(waited_too_long);
  // The writer writes at most the rows final when the sight stage failed (a little over 2048: a
  // thread may finish the chunk it held), then stops, far from Monaco's 37 093.
  EXPECT_LT(rows_begun.load(), 8192u);
  EXPECT_LE(batches_after_failure.load(), 24);
  EXPECT_TRUE(files_in(dir).empty()) << "left: " << files_in(dir).front();
}

TEST(SegmentRowsDuringSight, SmallBatchesGiveTheSameMap) {
  // The rows' batches follow the sight threads' progress: any batch size gives the same file.
  TempDir dir;
  rp::BuildOptions options = monaco_options(dir);
  const rp::BuildSummary small = rp::run_build(options);
  options.test_hooks = {};
  options.output_path = dir.file("default.gpkg");
  const rp::BuildSummary standard = rp::run_build(options);
  ASSERT_FALSE(small.stages.empty());
  EXPECT_EQ(small.stages.back().summary, standard.stages.back().summary);  // "map_id ..."
}

}  // namespace
