// Where a RowSource puts its values: SQLite (a virtual table column's result), a row for a
// table's digester (mapcheck::ColumnsDigester), or both at once. A source writes each value once
// through a template over these sinks, so the file and its digests get the same values, and
// with FedRowDigests the values SQLite pulls through insert_rows() are digested as they are
// handed over, not computed a second time for the digester.
#pragma once

#include <sqlite3.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "roadcross/mapcheck/content_hash.hpp"

namespace roadcross::preprocess {

/// Values handed to SQLite as a virtual table column's result.
struct SqliteValue {
  sqlite3_context* out;
  void null() {}  // no sqlite3_result_*: NULL
  void integer(std::int64_t value) { sqlite3_result_int64(out, value); }
  void real(double value) { sqlite3_result_double(out, value); }
  /// A text that outlives the insert (interned, or a static name): not copied.
  void lasting_text(std::string_view text) {
    sqlite3_result_text(out, text.data(), static_cast<int>(text.size()), SQLITE_STATIC);
  }
  void text(std::string_view text) {
    sqlite3_result_text(out, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  }
  void blob(const std::vector<std::uint8_t>& bytes) {
    // An empty vector's data() may be null, which SQLite would store as NULL, not as the empty
    // blob the digests take.
    static constexpr std::uint8_t kNoBytes = 0;
    sqlite3_result_blob(out, bytes.empty() ? &kNoBytes : bytes.data(),
                        static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
  }
};

/// The same values gathered into a row for the table's digester, which takes each through its
/// column's affinity as SQLite stores it. A text or blob that does not outlive the call is kept
/// here, one buffer a column (reused row after row), until the row is digested.
template <std::size_t kColumns>
class DigestedRow {
 public:
  void null() { add({}); }
  void integer(std::int64_t value) { add(mapcheck::RowValue::of_integer(value)); }
  void real(double value) { add(mapcheck::RowValue::of_real(value)); }
  void lasting_text(std::string_view text) { add(mapcheck::RowValue::of_text(text)); }
  void text(std::string_view text) {
    std::string& kept = texts_.at(next_);
    kept.assign(text);
    add(mapcheck::RowValue::of_text(kept));
  }
  void blob(std::vector<std::uint8_t> bytes) {
    std::vector<std::uint8_t>& kept = blobs_.at(next_);
    kept = std::move(bytes);
    add(mapcheck::RowValue::of_blob({reinterpret_cast<const char*>(kept.data()), kept.size()}));
  }
  /// Values added to the current row so far.
  std::size_t size() const { return next_; }
  /// Hands the row to `digester` and starts the next one.
  void digest(mapcheck::ColumnsDigester& digester) {
    const std::size_t count = next_;
    next_ = 0;
    digester.add_row({values_.data(), count});
  }

 private:
  void add(const mapcheck::RowValue& value) { values_.at(next_++) = value; }
  std::array<mapcheck::RowValue, kColumns> values_{};
  std::array<std::string, kColumns> texts_;
  std::array<std::vector<std::uint8_t>, kColumns> blobs_;
  std::size_t next_ = 0;
};

/// Each value to SQLite and to the row being digested: computed once for both.
template <std::size_t kColumns>
struct SqliteAndDigestedValue {
  SqliteValue sqlite;
  DigestedRow<kColumns>& digested;
  void null() { digested.null(); }
  void integer(std::int64_t value) {
    sqlite.integer(value);
    digested.integer(value);
  }
  void real(double value) {
    sqlite.real(value);
    digested.real(value);
  }
  void lasting_text(std::string_view text) {
    sqlite.lasting_text(text);
    digested.lasting_text(text);
  }
  void text(std::string_view text) {
    sqlite.text(text);
    digested.text(text);
  }
  void blob(std::vector<std::uint8_t> bytes) {
    sqlite.blob(bytes);
    digested.blob(std::move(bytes));
  }
};

/// The digests of the rows a RowSource hands to SQLite through insert_rows(), taken from the
/// values as they are handed over. The source's column() calls column() here with its own
/// value-writing function. SQLite asks an INSERT ... SELECT's virtual table for each row's
/// columns once, in order (the statement copies them into the record's registers one after the
/// other); a column asked for out of that order throws std::logic_error (the insert fails)
/// rather than digest a row that is not the one written. With `rowid_column` the source's column
/// 0 is its ascending_rowid(), which insert_rows hands to SQLite itself (as NULL, mostly): the
/// digester gets the rowid as the table stores it, given with the row's first other column.
template <std::size_t kColumns>
class FedRowDigests {
 public:
  FedRowDigests(mapcheck::ColumnsDigester& digester, bool rowid_column)
      : digester_(digester), first_column_(rowid_column ? 1 : 0) {}

  /// Value `column` of the row whose rowid is `rowid` (used when rowid_column): `put(sink)`
  /// writes it into a SqliteAndDigestedValue over `out`. Hands the row to the digester after
  /// its last column.
  template <typename Put>
  void column(int column, std::int64_t rowid, sqlite3_context* out, Put&& put) {
    if (column != next_column_) {
      throw std::logic_error("a fed row's digests: column " + std::to_string(column) +
                             " asked for where column " + std::to_string(next_column_) +
                             " was next");
    }
    if (column == first_column_ && first_column_ == 1) row_.integer(rowid);
    SqliteAndDigestedValue<kColumns> sink{SqliteValue{out}, row_};
    std::forward<Put>(put)(sink);
    if (row_.size() != static_cast<std::size_t>(column) + 1) {
      throw std::logic_error("a fed row's digests: column " + std::to_string(column) +
                             " put no single value");
    }
    if (++next_column_ == static_cast<int>(kColumns)) {
      row_.digest(digester_);
      next_column_ = first_column_;
    }
  }

  /// True between rows (every column asked for has been digested with its row).
  bool between_rows() const { return next_column_ == first_column_; }

 private:
  mapcheck::ColumnsDigester& digester_;
  int first_column_;
  int next_column_ = first_column_;
  DigestedRow<kColumns> row_;
};

}  // namespace roadcross::preprocess
