// Bulk inserts into SQLite as one INSERT ... SELECT statement over rows the build computes on
// demand, read through a virtual table. A prepared INSERT bound and stepped once per row costs
// a statement execution per row (cursor opened and closed, bindings copied and cleared). Read
// through a virtual table, SQLite keeps one statement and one cursor open for all rows and pulls
// each value straight from the build's own data.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string_view>

struct sqlite3;
struct sqlite3_context;

namespace roadcross::mapcheck {
class ColumnsDigester;
}

namespace roadcross::preprocess {

/// Rows produced on demand for insert_rows().
class RowSource {
 public:
  virtual ~RowSource() = default;
  virtual std::size_t row_count() const = 0;
  virtual int column_count() const = 0;
  /// Sets value `column` (0-based, < column_count()) of row `row` (0-based, < row_count()) with
  /// one of the sqlite3_result_*() functions (none: NULL). Rows are asked for in order. May
  /// throw: the insert then fails with the exception's message.
  virtual void column(std::size_t row, int column, sqlite3_context* out) const = 0;
  /// Row `row`'s rowid, when column 0 is the table's rowid (INTEGER PRIMARY KEY) and rows come
  /// in ascending rowid order; column() is then not asked for column 0. insert_rows passes a
  /// rowid one more than the previous row's as NULL: SQLite gives the row the table's largest
  /// rowid plus one, the same number, and appends it without searching the B-tree twice for it
  /// (a conflict check, then the insert's own search). The table's rows must all have smaller
  /// rowids than the first row's (insert_rows checks the last row's rowid). nullopt (the
  /// default): column 0 is an ordinary column.
  virtual std::optional<std::int64_t> ascending_rowid(std::size_t /*row*/) const {
    return std::nullopt;
  }
  /// Hands row `row`'s values, as column() gives them to SQLite, to `digester` as one row
  /// (ColumnsDigester::add_row; the rowid as the table gets it, not NULL): the per-row hook with
  /// which whoever feeds the rows computes the table's digests from them (rows in the table's
  /// hashed order, one thread). The default throws std::logic_error: a source without digests.
  virtual void digest_row(std::size_t row, mapcheck::ColumnsDigester& digester) const;
};

/// Runs `INSERT INTO <table> (<column_list>) SELECT * FROM <virtual table over source>` on `db`
/// (in the caller's transaction); `column_list` names source.column_count() columns, comma
/// separated. `on_progress(rows_done)` is called every 4096 rows. Throws sqlite::sqlite_error
/// with SQLite's message (or a RowSource exception's) on failure, and std::logic_error when not
/// every row was inserted (a table whose constraints ignore conflicts, say) or an
/// ascending_rowid() source's last row did not get its rowid (the table had larger ones).
void insert_rows(sqlite3* db, std::string_view table, std::string_view column_list,
                 const RowSource& source,
                 const std::function<void(std::size_t rows_done)>& on_progress = {});

}  // namespace roadcross::preprocess
