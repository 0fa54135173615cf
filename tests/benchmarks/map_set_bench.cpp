// Assess over a set of 10 maps against assess on one map (issue 29: at most 1.5x). The 10 maps
// are the bundled Prague map moved by whole degrees of longitude (copy k at +k degrees: UTM
// zones 33 and 34), built once into $ROADCROSS_BENCH_SET_DIR (default
// /tmp/roadcross-bench-set). Both benchmarks take WGS84 positions within 15 m of a road, so
// both pay the projection: one map answers positions in its own area, the set positions spread
// over all 10 maps (copy k's positions are copy 0's moved by k degrees). Per-call percentiles
// as counters p50_us / p99_us. Run: scripts/bench-map-set.sh
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "roadcross/map_set.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"

namespace {

constexpr int kMaps = 10;

std::string set_dir() {
  const char* given = std::getenv("ROADCROSS_BENCH_SET_DIR");
  return given ? given : "/tmp/roadcross-bench-set";
}

/// The Prague OSM text with every lon="..." moved by `shift_deg`.
std::string shifted_osm(const std::string& text, int shift_deg) {
  static const std::regex lon(R"(lon="([-0-9.]+)\")");
  std::string out;
  std::sregex_iterator it(text.begin(), text.end(), lon), end;
  std::size_t last = 0;
  for (; it != end; ++it) {
    out.append(text, last, it->position() - last);
    char value[64];
    std::snprintf(value, sizeof value, "lon=\"%.7f\"", std::stod((*it)[1]) + shift_deg);
    out += value;
    last = it->position() + it->length();
  }
  out.append(text, last, std::string::npos);
  return out;
}

/// Paths of the 10 maps, built on first use.
const std::vector<std::string>& maps() {
  static const std::vector<std::string> paths = [] {
    const std::string dir = set_dir();
    std::filesystem::create_directories(dir);
    std::ifstream in(std::string(ROADCROSS_MAPS_DIR) + "/prague/prague_nove_mesto_roads_2017.osm");
    std::stringstream text;
    text << in.rdbuf();
    std::vector<std::string> out;
    for (int k = 0; k < kMaps; ++k) {
      const std::string map = dir + "/prague_plus_" + std::to_string(k) + "deg.gpkg";
      if (!std::filesystem::exists(map)) {
        const std::string osm = dir + "/prague_plus_" + std::to_string(k) + "deg.osm";
        std::ofstream(osm) << shifted_osm(text.str(), k);
        roadcross::preprocess::BuildOptions options;
        options.osm_path = osm;
        options.output_path = map;
        roadcross::preprocess::run_build(options);
        std::filesystem::remove(osm);
      }
      out.push_back(map);
    }
    return out;
  }();
  return paths;
}

/// 4096 WGS84 positions within 15 m of a road of copy 0 (fixed seed); with `spread`, position i
/// is moved to copy i % 10.
std::vector<roadcross::Position> positions(bool spread) {
  auto map = roadcross::Map::open(maps()[0]);
  const auto& info = map->info();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> east(info.min_easting_m, info.max_easting_m);
  std::uniform_real_distribution<double> north(info.min_northing_m, info.max_northing_m);
  std::vector<roadcross::Position> out;
  while (out.size() < 4096) {
    const auto p = roadcross::Position::utm(east(random), north(random));
    if (!map->nearest(p, 15.0).ok()) continue;
    const roadcross::geo::LatLon ll = roadcross::geo::utm_to_wgs84(p.first, p.second, info.zone);
    const int shift = spread ? static_cast<int>(out.size() % kMaps) : 0;
    out.push_back(roadcross::Position::wgs84(ll.lat_deg, ll.lon_deg + shift));
  }
  return out;
}

template <typename Call>
void timed_loop(benchmark::State& state, const std::vector<roadcross::Position>& queries,
                Call&& call) {
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

void BM_AssessOneMap(benchmark::State& state) {
  auto map = roadcross::Map::open(maps()[0]);
  const auto queries = positions(false);
  timed_loop(state, queries, [&](const roadcross::Position& p) {
    auto a = map->assess(p);
    if (!a.ok()) state.SkipWithError(a.status.message.c_str());
    benchmark::DoNotOptimize(a);
  });
}
BENCHMARK(BM_AssessOneMap)->Unit(benchmark::kMicrosecond);

void BM_AssessSetOf10(benchmark::State& state) {
  auto set = roadcross::MapSet::open(maps());
  const auto queries = positions(true);
  timed_loop(state, queries, [&](const roadcross::Position& p) {
    auto a = set->assess(p);
    if (!a.ok()) state.SkipWithError(a.status.message.c_str());
    benchmark::DoNotOptimize(a);
  });
}
BENCHMARK(BM_AssessSetOf10)->Unit(benchmark::kMicrosecond);

/// The set answering positions of copy 0 only: what choosing among 10 maps adds when the data
/// (pages, statement caches) is that of one map, as in BM_AssessOneMap.
void BM_AssessSetOf10OneArea(benchmark::State& state) {
  auto set = roadcross::MapSet::open(maps());
  const auto queries = positions(false);
  timed_loop(state, queries, [&](const roadcross::Position& p) {
    auto a = set->assess(p);
    if (!a.ok()) state.SkipWithError(a.status.message.c_str());
    benchmark::DoNotOptimize(a);
  });
}
BENCHMARK(BM_AssessSetOf10OneArea)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
