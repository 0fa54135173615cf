// disable_sqlite_memory_statistics() is process-wide and works only before SQLite's first use,
// so each case runs in a fresh process: gtest's "threadsafe" death-test style re-executes this
// binary for the one statement, where nothing has touched SQLite yet.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <cstdlib>

#include "roadcross/runtime.hpp"

namespace {

/// Opens an in-memory database and writes a table: SQLite allocates, and with its memory
/// statistics on, sqlite3_memory_used() counts it.
sqlite3_int64 memory_used_after_some_work() {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(":memory:", &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) std::exit(3);
  sqlite3_exec(db, "CREATE TABLE t(x); INSERT INTO t VALUES (randomblob(10000));", nullptr, nullptr,
               nullptr);
  const sqlite3_int64 used = sqlite3_memory_used();
  sqlite3_close(db);
  return used;
}

}  // namespace

TEST(SqliteMemoryStatisticsDeathTest, OnByDefault) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(std::exit(memory_used_after_some_work() > 10000 ? 0 : 1), testing::ExitedWithCode(0),
              "");
}

TEST(SqliteMemoryStatisticsDeathTest, OffWhenDisabledBeforeFirstUse) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      std::exit(roadcross::disable_sqlite_memory_statistics() && memory_used_after_some_work() == 0
                    ? 0
                    : 1),
      testing::ExitedWithCode(0), "");
}

TEST(SqliteMemoryStatisticsDeathTest, TooLateOnceSqliteIsInitialised) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(std::exit(sqlite3_initialize() == SQLITE_OK &&
                                !roadcross::disable_sqlite_memory_statistics() &&
                                memory_used_after_some_work() > 10000
                            ? 0
                            : 1),
              testing::ExitedWithCode(0), "");
}
