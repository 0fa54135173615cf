// Runtime latency on the bundled Prague map (or the DB in $ROADCROSS_BENCH_DB): open, nearest,
// assess (exact and with a 3 m position sigma), better_place, and a bare SQLite R*Tree lookup on
// the same DB for comparison; assess on 1 and 2 threads (one Map per thread). Per-call
// percentiles are reported as counters p50_us / p99_us. Run: scripts/bench-runtime.sh
#include <benchmark/benchmark.h>
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"

namespace {

const std::string& database() {
  static const std::string path = [] {
    if (const char* given = std::getenv("ROADCROSS_BENCH_DB")) return std::string(given);
    const std::string out = "/tmp/roadcross-bench-prague.gpkg";
    roadcross::preprocess::BuildOptions options;
    options.osm_path = std::string(ROADCROSS_MAPS_DIR) + "/prague/prague_nove_mesto_roads_2017.osm";
    options.output_path = out;
    roadcross::preprocess::run_build(options);
    return out;
  }();
  return path;
}

/// Query positions where a robot asks: within 15 m of a road (a random point of the extent,
/// kept when nearest() finds a road within 15 m), or anywhere in the extent when
/// ROADCROSS_BENCH_ANYWHERE is set. Fixed seed.
std::vector<roadcross::Position> positions(std::size_t count) {
  auto map = roadcross::Map::open(database());
  const auto& info = map->info();
  const bool anywhere = std::getenv("ROADCROSS_BENCH_ANYWHERE") != nullptr;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> east(info.min_easting_m, info.max_easting_m);
  std::uniform_real_distribution<double> north(info.min_northing_m, info.max_northing_m);
  std::vector<roadcross::Position> out;
  while (out.size() < count) {
    const auto p = roadcross::Position::utm(east(random), north(random));
    if (anywhere || map->nearest(p, 15.0).ok()) out.push_back(p);
  }
  return out;
}

template <typename Call>
void timed_loop(benchmark::State& state, Call&& call) {
  const auto queries = positions(4096);
  std::vector<double> latencies_us;
  latencies_us.reserve(1 << 16);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    call(queries[i++ % queries.size()]);
    latencies_us.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(latencies_us.begin(), latencies_us.end());
  state.counters["p50_us"] = latencies_us[latencies_us.size() / 2];
  state.counters["p99_us"] = latencies_us[latencies_us.size() * 99 / 100];
}

void BM_Open(benchmark::State& state) {
  database();
  for (auto _ : state) {
    auto map = roadcross::Map::open(database());
    benchmark::DoNotOptimize(map.ok());
  }
}
BENCHMARK(BM_Open)->Unit(benchmark::kMillisecond);

void BM_Nearest(benchmark::State& state) {
  auto map = roadcross::Map::open(database());
  timed_loop(state,
             [&](const roadcross::Position& p) { benchmark::DoNotOptimize(map->nearest(p).ok()); });
}
BENCHMARK(BM_Nearest)->Unit(benchmark::kMicrosecond);

void BM_Assess(benchmark::State& state) {
  static thread_local std::optional<roadcross::Map> map;  // one Map (connection) per thread
  if (!map) map.emplace(std::move(*roadcross::Map::open(database()).value));
  timed_loop(state,
             [&](const roadcross::Position& p) { benchmark::DoNotOptimize(map->assess(p).ok()); });
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Assess)->Unit(benchmark::kMicrosecond)->Threads(1)->Threads(2)->UseRealTime();

// Exact and uncertain assess interleaved on the same positions, so that one run gives their
// ratio under the same load (issue: a 3 m sigma within 3x an exact assess).
void BM_AssessExactForSigma(benchmark::State& state) {
  auto map = roadcross::Map::open(database());
  timed_loop(state,
             [&](const roadcross::Position& p) { benchmark::DoNotOptimize(map->assess(p).ok()); });
}
BENCHMARK(BM_AssessExactForSigma)->Unit(benchmark::kMicrosecond);

void BM_AssessSigma3m(benchmark::State& state) {
  auto map = roadcross::Map::open(database());
  timed_loop(state, [&](const roadcross::Position& p) {
    benchmark::DoNotOptimize(map->assess(p.with_sigma(3.0)).ok());
  });
}
BENCHMARK(BM_AssessSigma3m)->Unit(benchmark::kMicrosecond);

void BM_BetterPlace100m(benchmark::State& state) {
  auto map = roadcross::Map::open(database());
  timed_loop(state, [&](const roadcross::Position& p) {
    benchmark::DoNotOptimize(map->better_place(p).ok());
  });
}
BENCHMARK(BM_BetterPlace100m)->Unit(benchmark::kMicrosecond);

// The floor assess is compared with: one R*Tree window query of 64 m around the position that
// reads the matching ids, on its own connection (default settings), prepared once.
// BM_BareRtreeLookupLikeMap sets the connection up as Map::open does (shared lock kept, pages
// memory-mapped, an R*Tree cursor held open): the floor under the runtime's own settings.
void bare_rtree_lookup(benchmark::State& state, bool like_map) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(database().c_str(), &db, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX, nullptr);
  sqlite3_stmt* holder = nullptr;  // an R*Tree cursor kept open, as Map keeps one
  if (like_map) {
    sqlite3_exec(db, "PRAGMA locking_mode = EXCLUSIVE; PRAGMA mmap_size = 1073741824", nullptr,
                 nullptr, nullptr);
    sqlite3_prepare_v2(db, "SELECT id FROM rtree_segments_geom LIMIT 1", -1, &holder, nullptr);
    sqlite3_step(holder);
  }
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(
      db,
      "SELECT id FROM rtree_segments_geom WHERE maxx >= ?1 AND minx <= ?2 AND maxy >= ?3 "
      "AND miny <= ?4",
      -1, &stmt, nullptr);
  timed_loop(state, [&](const roadcross::Position& p) {
    sqlite3_bind_double(stmt, 1, p.first - 32);
    sqlite3_bind_double(stmt, 2, p.first + 32);
    sqlite3_bind_double(stmt, 3, p.second - 32);
    sqlite3_bind_double(stmt, 4, p.second + 32);
    std::int64_t sum = 0;
    while (sqlite3_step(stmt) == SQLITE_ROW) sum += sqlite3_column_int64(stmt, 0);
    sqlite3_reset(stmt);
    benchmark::DoNotOptimize(sum);
  });
  sqlite3_finalize(stmt);
  sqlite3_finalize(holder);
  sqlite3_close(db);
}
void BM_BareRtreeLookup(benchmark::State& state) {
  bare_rtree_lookup(state, false);
}
BENCHMARK(BM_BareRtreeLookup)->Unit(benchmark::kMicrosecond);

void BM_BareRtreeLookupLikeMap(benchmark::State& state) {
  bare_rtree_lookup(state, true);
}
BENCHMARK(BM_BareRtreeLookupLikeMap)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // As a multi-threaded host should (runtime.hpp); ROADCROSS_BENCH_SQLITE_MEMSTATUS=1 keeps
  // SQLite's default, to measure what the setting buys.
  if (std::getenv("ROADCROSS_BENCH_SQLITE_MEMSTATUS") == nullptr) {
    roadcross::disable_sqlite_memory_statistics();
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
