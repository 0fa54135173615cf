// Bulk inserts into SQLite as one INSERT ... SELECT statement over rows the build computes on
// demand, read through a virtual table. A prepared INSERT bound and stepped once per row costs
// a statement execution per row (cursor opened and closed, bindings copied and cleared). Read
// through a virtual table, SQLite keeps one statement and one cursor open for all rows and pulls
// each value straight from the build's own data.
#pragma once

#include <cstddef>
#include <functional>
#include <string_view>

struct sqlite3;
struct sqlite3_context;

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
};

/// Runs `INSERT INTO <table> (<column_list>) SELECT * FROM <virtual table over source>` on `db`
/// (in the caller's transaction); `column_list` names source.column_count() columns, comma
/// separated. `on_progress(rows_done)` is called every 4096 rows. Throws sqlite::sqlite_error
/// with SQLite's message (or a RowSource exception's) on failure.
void insert_rows(sqlite3* db, std::string_view table, std::string_view column_list,
                 const RowSource& source,
                 const std::function<void(std::size_t rows_done)>& on_progress = {});

}  // namespace roadcross::preprocess
