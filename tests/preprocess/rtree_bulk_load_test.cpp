// The bulk-loaded R*Tree must be exactly what SQLite builds by inserting the same rows, as far
// as SQLite can tell: the same (id, box) rows, and SQLite's own rtreecheck() finds it consistent.
#include <gtest/gtest.h>

#include <random>

#include "roadcross/preprocess/output/rtree_bulk_load.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace sqlite = roadcross::sqlite;

namespace {

std::vector<rp::RtreeEntry> random_boxes(std::size_t count, unsigned seed) {
  std::mt19937 random(seed);
  // UTM-like magnitudes: float32 rounding matters at 5e6 m.
  std::uniform_real_distribution<double> east(400000.0, 420000.0), north(5540000.0, 5560000.0),
      size(0.0, 15.0);
  std::vector<rp::RtreeEntry> entries(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double x = east(random), y = north(random);
    entries[i] = {static_cast<std::int64_t>(i) * 3 + 1, {x, x + size(random), y, y + size(random)}};
  }
  return entries;
}

std::int64_t scalar(sqlite::Database& db, const std::string& sql) {
  auto statement = db.prepare(sql);
  EXPECT_TRUE(statement.step()) << sql;
  return statement.column_int64(0);
}

class RtreeBulkLoad : public ::testing::TestWithParam<std::size_t> {};

TEST_P(RtreeBulkLoad, MatchesSqliteInsertsAndPassesRtreecheck) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE VIRTUAL TABLE inserted USING rtree(id, minx, maxx, miny, maxy)");
  db.exec("CREATE VIRTUAL TABLE loaded USING rtree(id, minx, maxx, miny, maxy)");
  std::vector<rp::RtreeEntry> entries = random_boxes(GetParam(), 42);
  auto insert = db.prepare("INSERT INTO inserted VALUES (?, ?, ?, ?, ?)");
  for (const auto& e : entries) {
    insert.bind(1, e.id);
    insert.bind(2, e.box.min_x);
    insert.bind(3, e.box.max_x);
    insert.bind(4, e.box.min_y);
    insert.bind(5, e.box.max_y);
    insert.run();
  }
  rp::bulk_load_rtree(db.handle(), "loaded", entries);

  EXPECT_EQ(scalar(db, "SELECT count(*) FROM loaded"), static_cast<std::int64_t>(GetParam()));
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM (SELECT * FROM inserted EXCEPT SELECT * FROM loaded)"),
            0);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM (SELECT * FROM loaded EXCEPT SELECT * FROM inserted)"),
            0);
  auto check = db.prepare("SELECT rtreecheck('loaded')");
  ASSERT_TRUE(check.step());
  EXPECT_EQ(check.column_text(0), "ok");
  // A window query through the index returns what a scan of the rows returns.
  const std::string window =
      "maxx >= 405000 AND minx <= 407000 AND maxy >= 5545000 AND miny <= 5547000";
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM loaded WHERE " + window),
            scalar(db, "SELECT count(*) FROM inserted WHERE " + window));
}

// 0 and 1 entries, one full node (51 cells with 4 KiB pages), one more than a node, and sizes
// that need three and four levels.
INSTANTIATE_TEST_SUITE_P(Sizes, RtreeBulkLoad, ::testing::Values(0, 1, 51, 52, 2700, 140000));

}  // namespace

namespace {

// 52 equal boxes share one place on the Hilbert curve, so the leaves hold them in id order:
// the first 51 ids fill leaf node 2, the last one is alone in leaf node 3, and the root (node 1)
// is the parent of both.
TEST(RtreeBulkLoadLayout, TiesGoInIdOrderAndEachIdMapsToItsLeaf) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE VIRTUAL TABLE loaded USING rtree(id, minx, maxx, miny, maxy)");
  std::vector<rp::RtreeEntry> entries;
  for (std::int64_t id = 10; id < 10 + 52; ++id) entries.push_back({id, {1.0, 2.0, 3.0, 4.0}});
  rp::bulk_load_rtree(db.handle(), "loaded", entries);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM loaded_rowid WHERE nodeno = 2"), 51);
  EXPECT_EQ(scalar(db, "SELECT max(rowid) FROM loaded_rowid WHERE nodeno = 2"), 60);
  EXPECT_EQ(scalar(db, "SELECT rowid FROM loaded_rowid WHERE nodeno = 3"), 61);
  EXPECT_EQ(scalar(db, "SELECT count(*) FROM loaded_parent WHERE parentnode = 1"), 2);
  auto check = db.prepare("SELECT rtreecheck('loaded')");
  ASSERT_TRUE(check.step());
  EXPECT_EQ(check.column_text(0), "ok");
}

TEST(RtreeBulkLoadLayout, RefusesIdsThatDoNotAscend) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE VIRTUAL TABLE loaded USING rtree(id, minx, maxx, miny, maxy)");
  const std::vector<rp::RtreeEntry> entries = {{2, {0, 1, 0, 1}}, {1, {5, 6, 5, 6}}};
  EXPECT_THROW(rp::bulk_load_rtree(db.handle(), "loaded", entries), std::invalid_argument);
}

}  // namespace
