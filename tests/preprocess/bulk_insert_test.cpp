// insert_rows(): rows pulled through a virtual table arrive exactly as bound inserts would
// write them (types, NULLs, texts, blobs, order), twice on one connection, with progress, and a
// RowSource's exception, an interrupt or a constraint violation fails the insert, and so does a row
// the table drops (a conflict clause that ignores): a table's digests from its rows count on all.
// FedRowDigests: the digests of the values handed to SQLite equal those read back from the table,
// and a row lacking a value fails the insert.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/preprocess/output/bulk_insert.hpp"
#include "roadcross/preprocess/output/row_values.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace mc = roadcross::mapcheck;
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

/// Hand-made rows of every kind of value (NULLs, integers, reals with NaN, -0.0, infinities and
/// integral ones, lasting and copied texts, blobs, one empty) into columns of every affinity,
/// fids ascending with gaps; the values are handed to SQLite and its digests by FedRowDigests.
class MixedRows final : public rp::RowSource {
 public:
  static constexpr int kColumns = 8;
  MixedRows(std::vector<std::int64_t> fids, std::size_t first_value,
            rp::FedRowDigests<kColumns>* fed)
      : fids_(std::move(fids)), first_value_(first_value), fed_(fed) {}
  std::size_t row_count() const override { return fids_.size(); }
  int column_count() const override { return kColumns; }
  std::optional<std::int64_t> ascending_rowid(std::size_t row) const override { return fids_[row]; }
  void column(std::size_t row, int column, sqlite3_context* out) const override {
    fed_->column(first_value_ + row, column, out, [&](rp::DigestedRow<kColumns>& whole) {
      whole.integer(fids_[row]);
      for (int c = 1; c < kColumns; ++c) put(first_value_ + row, c, whole);
    });
  }

 private:
  template <typename Out>
  static void put(std::size_t v, int column, Out& out) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const auto i = static_cast<std::int64_t>(v);
    switch (column) {
      case 1:  // g LINESTRING (NUMERIC affinity)
        if (v % 5 == 4) return out.null();
        if (v % 5 == 3) return out.blob({});
        return out.blob({static_cast<std::uint8_t>(v), 0, 0xff});
      case 2:  // i INTEGER
        switch (v % 4) {
          case 0:
            return out.integer(i * 7 - 3);
          case 1:
            return out.real(2.0);  // stored as the integer 2
          case 2:
            return out.null();
          default:
            return out.real(0.25);
        }
      case 3: {  // r REAL
        const double reals[] = {0.5, nan, -0.0, 3.0, -inf, 1e300};
        if (v % 7 == 6) return out.integer(i);
        return out.real(reals[v % 7]);
      }
      case 4:  // b BOOLEAN
        return v % 3 == 2 ? out.null() : out.integer(i % 2);
      case 5: {  // t TEXT
        if (v % 4 == 1) return out.null();
        if (v % 4 == 2) return out.lasting_text("lasting");
        if (v % 4 == 3) return out.text(std::string_view("a\0b", 3));
        std::string text = "t";  // (not "t" + ...: GCC 12 warns falsely, -Wrestrict)
        text += std::to_string(v);
        return out.text(text);
      }
      case 6:  // x BLOB
        if (v % 3 == 0) return out.blob({1, 2, static_cast<std::uint8_t>(v)});
        return v % 3 == 1 ? out.real(nan) : out.null();
      case 7:  // u (no type)
        if (v % 3 == 0) return out.text("12");
        return v % 3 == 1 ? out.integer(-i) : out.real(-0.0);
    }
    throw std::logic_error("no column " + std::to_string(column));
  }

  std::vector<std::int64_t> fids_;
  std::size_t first_value_;
  rp::FedRowDigests<kColumns>* fed_;
};

const char* const kMixedTable =
    "CREATE TABLE segments (fid INTEGER PRIMARY KEY NOT NULL, g LINESTRING, i INTEGER, r REAL, "
    "b BOOLEAN, t TEXT, x BLOB, u)";
const char* const kMixedColumns = "fid, g, i, r, b, t, x, u";

/// The segments columns' digests compute_content_digest reads back from `db`.
std::vector<std::string> digests_read_back(sqlite::Database& db) {
  std::vector<std::string> digests;
  for (const mc::ColumnDigest& column : mc::compute_content_digest(db.handle()).columns) {
    if (column.table == "segments") digests.push_back(column.sha256_hex);
  }
  return digests;
}

TEST(BulkInsert, DigestsFromTheFeedEqualThoseOfTheWrittenTable) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE TABLE roadcross_metadata (key TEXT PRIMARY KEY, value TEXT)");
  db.exec(kMixedTable);
  mc::ColumnsDigester digester("segments", mc::declared_columns(db.handle(), "segments"));
  rp::FedRowDigests<MixedRows::kColumns> fed(digester);
  // Two batches through one digester, as the segments writer does; fids mostly consecutive
  // (handed to SQLite as NULL), some after a gap.
  std::vector<std::int64_t> first, second;
  std::int64_t fid = 3;
  for (int r = 0; r < 40; ++r) first.push_back(fid += (r % 9 == 0 ? 5 : 1));
  for (int r = 0; r < 44; ++r) second.push_back(fid += (r % 11 == 0 ? 3 : 1));
  db.exec("BEGIN");
  rp::insert_rows(db.handle(), "segments", kMixedColumns, MixedRows(first, 0, &fed));
  rp::insert_rows(db.handle(), "segments", kMixedColumns, MixedRows(second, first.size(), &fed));
  db.exec("COMMIT");
  const mc::WrittenTableDigest written = digester.finish();
  EXPECT_EQ(written.rows, first.size() + second.size());
  EXPECT_EQ(written.first_rowid, first.front());
  EXPECT_EQ(written.last_rowid, fid);

  std::vector<std::string> from_feed;
  for (const mc::ColumnDigest& column : written.digests) from_feed.push_back(column.sha256_hex);
  ASSERT_EQ(from_feed.size(), static_cast<std::size_t>(MixedRows::kColumns));
  EXPECT_EQ(from_feed, digests_read_back(db));

  // One value changed in the file: the digests read back differ in that column only.
  db.exec("UPDATE segments SET r = 0.75 WHERE fid = " + std::to_string(second[3]));
  const std::vector<std::string> changed = digests_read_back(db);
  ASSERT_EQ(changed.size(), from_feed.size());
  for (std::size_t c = 0; c < changed.size(); ++c) {
    EXPECT_EQ(changed[c] == from_feed[c], c != 3) << "column " << c;
  }
}

/// A source whose rows lack a value: the feed's digests refuse them and the insert fails.
class ShortRows final : public rp::RowSource {
 public:
  explicit ShortRows(rp::FedRowDigests<3>* fed) : fed_(fed) {}
  std::size_t row_count() const override { return 2; }
  int column_count() const override { return 3; }
  std::optional<std::int64_t> ascending_rowid(std::size_t row) const override {
    return static_cast<std::int64_t>(row) + 1;
  }
  void column(std::size_t row, int column, sqlite3_context* out) const override {
    fed_->column(row, column, out, [&](rp::DigestedRow<3>& whole) {
      whole.integer(static_cast<std::int64_t>(row) + 1);
      whole.integer(7);  // column 2 missing
    });
  }

 private:
  rp::FedRowDigests<3>* fed_;
};

TEST(BulkInsert, FeedDigestsOfARowLackingAValueFailTheInsert) {
  sqlite::Database db(":memory:", SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE TABLE segments (fid INTEGER PRIMARY KEY, a INTEGER, b INTEGER)");
  mc::ColumnsDigester digester("segments", mc::declared_columns(db.handle(), "segments"));
  rp::FedRowDigests<3> fed(digester);
  EXPECT_THROW(rp::insert_rows(db.handle(), "segments", "fid, a, b", ShortRows(&fed)),
               sqlite::sqlite_error);
}

}  // namespace
