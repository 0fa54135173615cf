// insert_rows(): rows pulled through a virtual table arrive exactly as bound inserts would
// write them (types, NULLs, texts, blobs, order), twice on one connection, with progress, and a
// RowSource's exception, an interrupt or a constraint violation fails the insert, and so does a row
// the table drops (a conflict clause that ignores): a table's digests from its rows count on all.
#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <vector>

#include "roadcross/preprocess/output/bulk_insert.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace sqlite = roadcross::sqlite;

namespace {

/// Row r: (r + 1, r * 0.5, "t<r>" or NULL for odd r, blob {r, r + 1}).
class NumberedRows final : public rp::RowSource {
 public:
  explicit NumberedRows(std::size_t rows, std::size_t throw_at_row = SIZE_MAX)
      : rows_(rows), throw_at_row_(throw_at_row) {}
  std::size_t row_count() const override { return rows_; }
  int column_count() const override { return 4; }
  void column(std::size_t row, int column, sqlite3_context* out) const override {
    if (row == throw_at_row_) throw std::runtime_error("row " + std::to_string(row) + " broken");
    switch (column) {
      case 0:
        return sqlite3_result_int64(out, static_cast<sqlite3_int64>(row) + 1);
      case 1:
        return sqlite3_result_double(out, static_cast<double>(row) * 0.5);
      case 2: {
        if (row % 2 == 1) return;  // NULL
        std::string text = "t";    // (not "t" + ...: GCC 12 warns falsely, -Wrestrict)
        text += std::to_string(row);
        return sqlite3_result_text(out, text.data(), static_cast<int>(text.size()),
                                   SQLITE_TRANSIENT);
      }
      case 3: {
        const unsigned char blob[2] = {static_cast<unsigned char>(row),
                                       static_cast<unsigned char>(row + 1)};
        return sqlite3_result_blob(out, blob, 2, SQLITE_TRANSIENT);
      }
    }
  }

 private:
  std::size_t rows_, throw_at_row_;
};

/// NumberedRows with the given ascending ids as column 0, the table's rowid.
class AscendingRows final : public rp::RowSource {
 public:
  explicit AscendingRows(std::vector<std::int64_t> ids)
      : ids_(std::move(ids)), values_(ids_.size()) {}
  std::size_t row_count() const override { return ids_.size(); }
  int column_count() const override { return 4; }
  std::optional<std::int64_t> ascending_rowid(std::size_t row) const override { return ids_[row]; }
  void column(std::size_t row, int column, sqlite3_context* out) const override {
    if (column == 0) throw std::logic_error("column 0 asked for");
    values_.column(row, column, out);
  }

 private:
  std::vector<std::int64_t> ids_;
  NumberedRows values_;
};

sqlite::Database table_db() {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x REAL NOT NULL, s TEXT, b BLOB)");
  return db;
}

std::string dump(sqlite::Database& db) {
  auto rows =
      db.prepare("SELECT id, typeof(x), x, typeof(s), ifnull(s, '-'), hex(b) FROM t ORDER BY id");
  std::string out;
  while (rows.step()) {
    out += std::to_string(rows.column_int64(0)) + " " + rows.column_text(1) + " " +
           rows.column_text(2) + " " + rows.column_text(3) + " " + rows.column_text(4) + " " +
           rows.column_text(5) + "\n";
  }
  return out;
}

TEST(BulkInsert, RowsArriveAsBoundInsertsWriteThem) {
  sqlite::Database by_feed = table_db();
  rp::insert_rows(by_feed.handle(), "t", "id, x, s, b", NumberedRows(3));
  EXPECT_EQ(dump(by_feed),
            "1 real 0.0 text t0 0001\n"
            "2 real 0.5 null - 0102\n"
            "3 real 1.0 text t2 0203\n");

  // The same rows through a prepared statement give the same table.
  sqlite::Database by_statement = table_db();
  auto insert = by_statement.prepare("INSERT INTO t (id, x, s, b) VALUES (?, ?, ?, ?)");
  for (int r = 0; r < 3; ++r) {
    const std::uint8_t blob[2] = {static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(r + 1)};
    insert.bind(1, std::int64_t{r + 1});
    insert.bind(2, r * 0.5);
    if (r % 2 == 0) {
      std::string text = "t";
      text += std::to_string(r);
      insert.bind(3, std::string_view(text));
    } else {
      insert.bind_null(3);
    }
    insert.bind(4, std::span<const std::uint8_t>(blob));
    insert.run();
  }
  EXPECT_EQ(dump(by_statement), dump(by_feed));
}

TEST(BulkInsert, ManyRowsTwiceOnOneConnectionWithProgress) {
  sqlite::Database db = table_db();
  db.exec("CREATE TABLE u (id INTEGER PRIMARY KEY, x REAL, s TEXT, b BLOB)");
  std::vector<std::size_t> reported;
  rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(10000),
                  [&](std::size_t done) { reported.push_back(done); });
  EXPECT_EQ(reported, (std::vector<std::size_t>{4096, 8192}));
  rp::insert_rows(db.handle(), "u", "id, x, s, b", NumberedRows(5));
  auto count = db.prepare(
      "SELECT (SELECT count(*) FROM t), (SELECT sum(id) FROM t), "
      "(SELECT count(*) FROM u), (SELECT count(s) FROM t)");
  ASSERT_TRUE(count.step());
  EXPECT_EQ(count.column_int64(0), 10000);
  EXPECT_EQ(count.column_int64(1), 10000LL * 10001 / 2);
  EXPECT_EQ(count.column_int64(2), 5);
  EXPECT_EQ(count.column_int64(3), 5000);  // the even rows
}

TEST(BulkInsert, EmptySourceInsertsNothing) {
  sqlite::Database db = table_db();
  rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(0));
  EXPECT_EQ(dump(db), "");
}

TEST(BulkInsert, SourceExceptionFailsTheInsertWithItsMessage) {
  sqlite::Database db = table_db();
  db.exec("BEGIN");
  try {
    rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(10, 7));
    FAIL() << "no exception";
  } catch (const sqlite::sqlite_error& e) {
    EXPECT_NE(std::string(e.what()).find("row 7 broken"), std::string::npos) << e.what();
  }
}

// The GeoPackage writer stops its side half this way when the other half failed: the progress
// call interrupts the connection's running insert, which fails before the source's end.
TEST(BulkInsert, InterruptFromTheProgressCallStopsTheInsert) {
  sqlite::Database db = table_db();
  db.exec("BEGIN");
  std::vector<std::size_t> reported;
  EXPECT_THROW(rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(20000),
                               [&](std::size_t done) {
                                 reported.push_back(done);
                                 if (done == 8192) sqlite3_interrupt(db.handle());
                               }),
               sqlite::sqlite_error);
  EXPECT_EQ(reported, (std::vector<std::size_t>{4096, 8192}));  // none after the interrupt
}

TEST(BulkInsert, ConstraintViolationFails) {
  sqlite::Database db = table_db();
  db.exec("INSERT INTO t VALUES (2, 0, NULL, NULL)");  // row 1 of the source has id 2
  EXPECT_THROW(rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(3)),
               sqlite::sqlite_error);
}

// Rowids one more than the previous row's reach SQLite as NULL (it appends them with its own
// next rowid, the same number); the others, and the first, as given.
TEST(BulkInsert, AscendingRowidsAreStoredAsGiven) {
  sqlite::Database db = table_db();
  db.exec("INSERT INTO t VALUES (2, 9, NULL, NULL)");  // smaller than the source's first id
  rp::insert_rows(db.handle(), "t", "id, x, s, b", AscendingRows({5, 6, 7, 10, 11, 13}));
  auto ids = db.prepare("SELECT group_concat(id, ' '), group_concat(x, ' ') FROM t");
  ASSERT_TRUE(ids.step());
  EXPECT_EQ(ids.column_text(0), "2 5 6 7 10 11 13");
  EXPECT_EQ(ids.column_text(1), "9.0 0.0 0.5 1.0 1.5 2.0 2.5");
}

TEST(BulkInsert, AscendingRowidsBelowTheTablesLargestFail) {
  sqlite::Database db = table_db();
  db.exec("BEGIN");
  db.exec("INSERT INTO t VALUES (100, 9, NULL, NULL)");
  // SQLite's next rowid would be 101, 102: the check of the last row's rowid fails.
  EXPECT_THROW(rp::insert_rows(db.handle(), "t", "id, x, s, b", AscendingRows({5, 6, 7})),
               std::logic_error);
}

TEST(BulkInsert, ARowTheTableIgnoresFails) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  // Row 1's s is NULL: the table drops that row instead of failing the statement.
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x REAL, s TEXT NOT NULL ON CONFLICT IGNORE, b)");
  EXPECT_THROW(rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(3)), std::logic_error);
  db.exec("DELETE FROM t");
  EXPECT_NO_THROW(rp::insert_rows(db.handle(), "t", "id, x, s, b", NumberedRows(1)));  // row 0
}

}  // namespace
