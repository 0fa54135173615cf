#include "roadcross/preprocess/output/bulk_insert.hpp"

#include <atomic>
#include <cstdint>
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>

#include "roadcross/schema/sqlite.hpp"

namespace roadcross::preprocess {

namespace {

/// What one insert_rows() call hands to its module.
struct RowFeed {
  const RowSource* source = nullptr;
  const std::function<void(std::size_t)>* on_progress = nullptr;
};

struct FeedTable {
  sqlite3_vtab base{};  // first: SQLite casts between the two
  const RowFeed* feed = nullptr;
};

struct FeedCursor {
  sqlite3_vtab_cursor base{};  // first: SQLite casts between the two
  const RowFeed* feed = nullptr;
  std::size_t row = 0;
  /// The last rowid handed on (ascending_rowid sources) and its row.
  std::int64_t last_rowid = 0;
  std::size_t last_rowid_row = SIZE_MAX;
};

int feed_connect(sqlite3* db, void* client_data, int /*argc*/, const char* const* /*argv*/,
                 sqlite3_vtab** out, char** /*error*/) {
  const auto* feed = static_cast<const RowFeed*>(client_data);
  std::string declaration = "CREATE TABLE x(";
  for (int c = 0; c < feed->source->column_count(); ++c) {
    declaration += (c == 0 ? "c" : ", c") + std::to_string(c);
  }
  declaration += ")";
  const int rc = sqlite3_declare_vtab(db, declaration.c_str());
  if (rc != SQLITE_OK) return rc;
  auto* table = new FeedTable;
  table->feed = feed;
  *out = &table->base;
  return SQLITE_OK;
}

int feed_disconnect(sqlite3_vtab* table) {
  delete reinterpret_cast<FeedTable*>(table);
  return SQLITE_OK;
}

int feed_best_index(sqlite3_vtab* table, sqlite3_index_info* info) {
  // One plan: every row, in order (no constraint is used).
  info->estimatedRows =
      static_cast<sqlite3_int64>(reinterpret_cast<FeedTable*>(table)->feed->source->row_count());
  info->estimatedCost = static_cast<double>(info->estimatedRows);
  return SQLITE_OK;
}

int feed_open(sqlite3_vtab* table, sqlite3_vtab_cursor** out) {
  auto* cursor = new FeedCursor;
  cursor->feed = reinterpret_cast<FeedTable*>(table)->feed;
  *out = &cursor->base;
  return SQLITE_OK;
}

int feed_close(sqlite3_vtab_cursor* cursor) {
  delete reinterpret_cast<FeedCursor*>(cursor);
  return SQLITE_OK;
}

int feed_filter(sqlite3_vtab_cursor* base, int, const char*, int, sqlite3_value**) {
  auto* cursor = reinterpret_cast<FeedCursor*>(base);
  cursor->row = 0;
  cursor->last_rowid_row = SIZE_MAX;
  return SQLITE_OK;
}

int feed_next(sqlite3_vtab_cursor* base) {
  auto* cursor = reinterpret_cast<FeedCursor*>(base);
  ++cursor->row;
  if (cursor->row % 4096 == 0 && cursor->feed->on_progress && *cursor->feed->on_progress) {
    (*cursor->feed->on_progress)(cursor->row);
  }
  return SQLITE_OK;
}

int feed_eof(sqlite3_vtab_cursor* base) {
  const auto* cursor = reinterpret_cast<FeedCursor*>(base);
  return cursor->row >= cursor->feed->source->row_count() ? 1 : 0;
}

/// Column 0 of a source with ascending rowids: NULL when SQLite's own next rowid (the largest
/// plus one, after the previous row's) is the row's.
void rowid_column(FeedCursor& cursor, std::int64_t rowid, sqlite3_context* out) {
  const bool next_after_previous =
      cursor.row > 0 && cursor.last_rowid_row == cursor.row - 1 && cursor.last_rowid + 1 == rowid;
  cursor.last_rowid = rowid;
  cursor.last_rowid_row = cursor.row;
  if (!next_after_previous) sqlite3_result_int64(out, rowid);
}

int feed_column(sqlite3_vtab_cursor* base, sqlite3_context* out, int column) {
  auto* cursor = reinterpret_cast<FeedCursor*>(base);
  try {
    const RowSource& source = *cursor->feed->source;
    const std::optional<std::int64_t> rowid =
        column == 0 ? source.ascending_rowid(cursor->row) : std::nullopt;
    if (rowid) {
      rowid_column(*cursor, *rowid, out);
    } else {
      source.column(cursor->row, column, out);
    }
  } catch (const std::exception& e) {
    sqlite3_result_error(out, e.what(), -1);
    return SQLITE_ERROR;
  }
  return SQLITE_OK;
}

int feed_rowid(sqlite3_vtab_cursor* base, sqlite3_int64* rowid) {
  *rowid = static_cast<sqlite3_int64>(reinterpret_cast<FeedCursor*>(base)->row) + 1;
  return SQLITE_OK;
}

sqlite3_module feed_module() {
  sqlite3_module module{};
  module.iVersion = 1;
  module.xCreate = nullptr;  // eponymous only: the table exists without CREATE VIRTUAL TABLE
  module.xConnect = feed_connect;
  module.xBestIndex = feed_best_index;
  module.xDisconnect = feed_disconnect;
  module.xDestroy = feed_disconnect;
  module.xOpen = feed_open;
  module.xClose = feed_close;
  module.xFilter = feed_filter;
  module.xNext = feed_next;
  module.xEof = feed_eof;
  module.xColumn = feed_column;
  module.xRowid = feed_rowid;
  return module;
}

}  // namespace

void RowSource::digest_row(std::size_t /*row*/, mapcheck::ColumnsDigester& /*digester*/) const {
  throw std::logic_error("this RowSource computes no digests of its rows");
}

void insert_rows(sqlite3* db, std::string_view table, std::string_view column_list,
                 const RowSource& source,
                 const std::function<void(std::size_t rows_done)>& on_progress) {
  static const sqlite3_module module = feed_module();
  // A fresh module name per call: the module's client data is this call's feed, and a name is
  // never re-registered on a connection (the names cost a few bytes until it closes).
  static std::atomic<unsigned> calls{0};
  const std::string name = "roadcross_feed_" + std::to_string(++calls);
  const RowFeed feed{&source, &on_progress};
  int rc =
      sqlite3_create_module_v2(db, name.c_str(), &module, const_cast<RowFeed*>(&feed), nullptr);
  if (rc != SQLITE_OK) {
    throw sqlite::sqlite_error(
        rc, "cannot register the bulk-insert module: " + std::string(sqlite3_errmsg(db)));
  }
  std::string quoted_table = "\"";  // (not "\"" + ...: GCC 12 warns falsely, -Wrestrict)
  quoted_table += table;
  quoted_table += '"';
  sqlite::Statement insert(db, "INSERT INTO " + quoted_table + " (" + std::string(column_list) +
                                   ") SELECT * FROM " + name);
  insert.run();
  const std::size_t rows = source.row_count();
  // Every row went in (what the table's digests computed from the source count on).
  if (const sqlite3_int64 inserted = sqlite3_changes64(db);
      inserted != static_cast<sqlite3_int64>(rows)) {
    throw std::logic_error("insert_rows: " + std::to_string(inserted) + " rows of " +
                           std::to_string(rows) + " went into " + std::string(table));
  }
  if (rows == 0 || !source.ascending_rowid(0)) return;
  sqlite::Statement last(db, "SELECT max(rowid) FROM " + quoted_table);
  if (!last.step() || last.column_int64(0) != *source.ascending_rowid(rows - 1)) {
    throw std::logic_error("insert_rows: the rows of " + std::string(table) +
                           " did not get their ascending rowids (larger ones were there)");
  }
}

}  // namespace roadcross::preprocess
