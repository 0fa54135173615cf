// The runtime's threading model under load: one Map (or MapSet) per thread, any number of
// threads, no shared state between them. These tests run in the ordinary builds and in the
// ThreadSanitizer build (preset `tsan`, scripts/test.sh --tsan), which is where they earn
// their keep: a data race in the runtime or in its use of SQLite fails them there.
//
// The map is written here with schema's own statements (no roadcross-build: the TSan build is
// the runtime-only one): a straight east-west road of 20 segments of 10 m and a side road
// joining it at its middle, in UTM zone 33N around Prague.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "roadcross/map_set.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"

namespace {

using roadcross::Map;
using roadcross::MapSet;
using roadcross::Position;
using roadcross::schema::PlanePoint;

constexpr double kOriginEastingM = 458000.0;
constexpr double kOriginNorthingM = 5547000.0;
constexpr int kMainSegments = 20;
constexpr double kSegmentLengthM = 10.0;
constexpr int kUtmZone = 33;
constexpr int kSrsId = 32633;

void exec(sqlite3* db, const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string message = error ? error : "?";
    sqlite3_free(error);
    throw std::runtime_error(sql.substr(0, 80) + ": " + message);
  }
}

/// One segment row: the identity, the score (15 - rank) and its reasons; every cost term the
/// runtime reads that may be NULL is NULL.
struct SegmentRow {
  std::int64_t fid, way, from_node, to_node;
  std::vector<PlanePoint> points;
  int rank;
  std::string reasons;
};

void insert_segment(sqlite3* db, const SegmentRow& row) {
  sqlite3_stmt* insert = nullptr;
  const std::string sql =
      "INSERT INTO segments (fid, geom, osm_way_id, highway, name, length_m, from_node_id, "
      "to_node_id, oneway, tunnel, bridge, class_cost, elevation_cost, context_score, rank, "
      "score, reasons) VALUES (?1, ?2, ?3, 'residential', 'Test Street', ?4, ?5, ?6, 0, 0, 0, 1, "
      "0, 0, ?7, ?8, ?9)";
  ASSERT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &insert, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db);
  const std::vector<std::uint8_t> blob = roadcross::schema::encode_linestring(row.points, kSrsId);
  double length_m = 0.0;
  for (std::size_t i = 1; i < row.points.size(); ++i) {
    length_m +=
        std::hypot(row.points[i].x - row.points[i - 1].x, row.points[i].y - row.points[i - 1].y);
  }
  sqlite3_bind_int64(insert, 1, row.fid);
  sqlite3_bind_blob(insert, 2, blob.data(), static_cast<int>(blob.size()), SQLITE_TRANSIENT);
  sqlite3_bind_int64(insert, 3, row.way);
  sqlite3_bind_double(insert, 4, length_m);
  sqlite3_bind_int64(insert, 5, row.from_node);
  sqlite3_bind_int64(insert, 6, row.to_node);
  sqlite3_bind_int(insert, 7, row.rank);
  sqlite3_bind_int(insert, 8, 15 - row.rank);
  sqlite3_bind_text(insert, 9, row.reasons.c_str(), -1, SQLITE_TRANSIENT);
  ASSERT_EQ(sqlite3_step(insert), SQLITE_DONE) << sqlite3_errmsg(db);
  sqlite3_finalize(insert);
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const PlanePoint& p : row.points) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  char rtree[256];
  std::snprintf(rtree, sizeof rtree,
                "INSERT INTO rtree_segments_geom VALUES (%lld, %.3f, %.3f, %.3f, %.3f)",
                static_cast<long long>(row.fid), min_x, max_x, min_y, max_y);
  exec(db, rtree);
}

/// Writes the test map to `path`: main road segments 1..20 west to east along northing 0
/// (relative to the origin), fid 1..20; the side road (fid 21, 22) north from the main road's
/// middle node. Segments 6..8 are suitable (rank 0, score 15 >= the map's threshold 13), the
/// others have rank 5 (score 10 < 13: LOW_SCORE).
void write_test_map(const std::string& path) {
  std::filesystem::remove(path);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  for (const std::string& statement :
       roadcross::schema::create_statements(kUtmZone, true, "2026-12-02T00:00:00.000Z")) {
    exec(db, statement);
  }
  exec(db, "BEGIN");
  for (int i = 0; i < kMainSegments; ++i) {
    const double west_m = i * kSegmentLengthM;
    SegmentRow row{i + 1,
                   100,
                   i,
                   i + 1,
                   {{kOriginEastingM + west_m, kOriginNorthingM},
                    {kOriginEastingM + west_m + kSegmentLengthM, kOriginNorthingM}},
                   (i >= 5 && i <= 7) ? 0 : 5,
                   ""};
    insert_segment(db, row);
  }
  const double middle_m = kMainSegments / 2 * kSegmentLengthM;
  for (int j = 0; j < 2; ++j) {
    SegmentRow row{21 + j,
                   200,
                   j == 0 ? kMainSegments / 2 : 1000 + j,
                   1001 + j,
                   {{kOriginEastingM + middle_m, kOriginNorthingM + j * kSegmentLengthM},
                    {kOriginEastingM + middle_m, kOriginNorthingM + (j + 1) * kSegmentLengthM}},
                   5,
                   ""};
    insert_segment(db, row);
  }
  char extent[300];
  std::snprintf(extent, sizeof extent,
                "UPDATE gpkg_contents SET min_x = %.3f, min_y = %.3f, max_x = %.3f, max_y = %.3f "
                "WHERE table_name = 'segments'",
                kOriginEastingM, kOriginNorthingM,
                kOriginEastingM + kMainSegments * kSegmentLengthM,
                kOriginNorthingM + 2 * kSegmentLengthM);
  exec(db, extent);
  const std::vector<std::pair<std::string_view, std::string>> metadata = {
      {roadcross::schema::meta::kSchemaVersion, std::to_string(roadcross::schema::kSchemaVersion)},
      {roadcross::schema::meta::kToolVersion, "concurrency_test"},
      {roadcross::schema::meta::kUtmZone, std::to_string(kUtmZone)},
      {roadcross::schema::meta::kUtmNorthern, "1"},
      {roadcross::schema::meta::kEpsg, std::to_string(kSrsId)},
      {roadcross::schema::meta::kSegmentCount, std::to_string(kMainSegments + 2)},
      {roadcross::schema::meta::kThresholdParam, "13"},
  };
  for (const auto& [key, value] : metadata) {
    exec(db, "INSERT INTO roadcross_metadata (key, value) VALUES ('" + std::string(key) + "', '" +
                 value + "')");
  }
  exec(db, "COMMIT");
  sqlite3_close(db);
}

class Concurrency : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    path_ = (std::filesystem::temp_directory_path() /
             ("roadcross-concurrency-" + std::to_string(::getpid()) + ".gpkg"))
                .string();
    write_test_map(path_);
  }
  static void TearDownTestSuite() { std::filesystem::remove(path_); }

  /// 2 m north of the main road at `east_m` along it (east of the origin).
  static Position beside(double east_m) {
    return Position::utm(kOriginEastingM + east_m, kOriginNorthingM - 2.0);
  }

  static std::string path_;
};
std::string Concurrency::path_;

TEST_F(Concurrency, TheHandMadeMapAnswersAsDerived) {
  // Segment k (1-based) spans east (k-1)*10 .. k*10 m: 55 m east lies on segment 6 (rank 0,
  // score 15 >= 13: suitable), 15 m east on segment 2 (score 10 < 13: LOW_SCORE).
  auto map = Map::open(path_);
  ASSERT_TRUE(map.ok()) << map.status.message;
  const auto good = map->assess(beside(55.0));
  ASSERT_TRUE(good.ok()) << good.status.message;
  EXPECT_EQ(good->road.segment_id, 6);
  EXPECT_NEAR(good->road.distance_m, 2.0, 1e-6);
  EXPECT_TRUE(good->suitable);
  const auto poor = map->assess(beside(15.0));
  ASSERT_TRUE(poor.ok()) << poor.status.message;
  EXPECT_EQ(poor->road.segment_id, 2);
  EXPECT_FALSE(poor->suitable);
}

TEST_F(Concurrency, OneMapPerThreadGivesTheSameAnswers) {
  // 200 positions along the road answered by one thread, then by 4 threads at once with their
  // own Map, 3 rounds each: every answer equal.
  std::vector<Position> queries;
  for (int i = 0; i < 200; ++i) queries.push_back(beside(0.5 + i * 0.99));
  auto reference = Map::open(path_);
  ASSERT_TRUE(reference.ok());
  std::vector<std::pair<std::int64_t, bool>> expected;
  for (const Position& q : queries) {
    const auto a = reference->assess(q);
    ASSERT_TRUE(a.ok()) << a.status.message;
    expected.emplace_back(a->road.segment_id, a->suitable);
  }
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      auto own = Map::open(path_);
      if (!own.ok()) {
        ++mismatches;
        return;
      }
      for (int round = 0; round < 3; ++round) {
        for (std::size_t i = 0; i < queries.size(); ++i) {
          const auto a = own->assess(queries[i]);
          if (!a.ok() || std::make_pair(a->road.segment_id, a->suitable) != expected[i])
            ++mismatches;
          const auto places = own->better_place(queries[i]);
          if (!places.ok()) ++mismatches;
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches.load(), 0);
}

TEST_F(Concurrency, OneMapSetPerThreadAndAMapHandedOverUnderAMutex) {
  // A MapSet per thread, and one Map shared by all threads but used under a mutex (the Python
  // binding's model: queries of several threads take turns on one connection).
  auto shared = Map::open(path_);
  ASSERT_TRUE(shared.ok());
  std::mutex shared_mutex;
  std::atomic<int> failures{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t) {
    threads.emplace_back([&, t] {
      auto set = MapSet::open({path_});
      if (!set.ok()) {
        ++failures;
        return;
      }
      for (int i = 0; i < 100; ++i) {
        const double east_m = 1.0 + ((i * 7 + t * 13) % 195);
        const auto from_set = set->nearest(
            Position::utm(kOriginEastingM + east_m, kOriginNorthingM - 2.0, {kUtmZone, true}));
        std::lock_guard<std::mutex> lock(shared_mutex);
        const auto from_shared = shared->nearest(beside(east_m));
        if (!from_set.ok() || !from_shared.ok() ||
            from_set->answer.segment_id != from_shared->segment_id) {
          ++failures;
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(failures.load(), 0);
}

}  // namespace
