// Where a RowSource puts its values: SQLite (a virtual table column's result) or a row for a
// table's digester (mapcheck::ColumnsDigester). A source writes each value through one template
// over these sinks, so the file and its digests get the same values; with FedRowDigests the rows
// SQLite pulls through insert_rows() are computed once, digested and handed to SQLite from the
// digested row, not computed a second time for the digester.
#pragma once

#include <sqlite3.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
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
  /// A blob that stays unchanged until the next row is asked for: copied all the same (SQLite
  /// may hold a value longer than this source can promise).
  void lasting_blob(std::span<const std::uint8_t> bytes) {
    static constexpr std::uint8_t kNoBytes = 0;
    sqlite3_result_blob(out, bytes.empty() ? &kNoBytes : bytes.data(),
                        static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
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
  /// A blob that stays unchanged until the next row is filled (viewed, not kept).
  void lasting_blob(std::span<const std::uint8_t> bytes) {
    add(mapcheck::RowValue::of_blob({reinterpret_cast<const char*>(bytes.data()), bytes.size()}));
  }
  void blob(std::vector<std::uint8_t> bytes) {
    std::vector<std::uint8_t>& kept = blobs_.at(next_);
    kept = std::move(bytes);
    add(mapcheck::RowValue::of_blob({reinterpret_cast<const char*>(kept.data()), kept.size()}));
  }
  /// Values added to the current row so far.
  std::size_t size() const { return next_; }
  /// Value `column` of the row last digested (its texts and blobs kept until the next row).
  const mapcheck::RowValue& value(std::size_t column) const { return values_.at(column); }
  /// Hands the row to `digester` and starts the next one (its values stay, for value()).
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

/// The digests of the rows a RowSource hands to SQLite through insert_rows(), each value
/// computed once for both. At the first column SQLite asks of a row, the row is filled whole
/// into a DigestedRow (its rowid first, as the table stores it: insert_rows mostly hands an
/// ascending rowid to SQLite as NULL) and handed to the digester; SQLite's columns are then
/// served from that row's values, in whatever order and as often as it asks. Rows must be asked
/// for in ascending order (as insert_rows does); each row asked for is digested once.
template <std::size_t kColumns>
class FedRowDigests {
 public:
  explicit FedRowDigests(mapcheck::ColumnsDigester& digester) : digester_(digester) {}

  /// Value `column` of row `row` (an index unique over all the rows fed to this digester, in
  /// ascending order) to `out`; on a new row `fill(row)` first puts every column of the row,
  /// column 0 included, into the DigestedRow it is given.
  template <typename Fill>
  void column(std::size_t row, int column, sqlite3_context* out, Fill&& fill) {
    if (!filled_ || row != row_index_) [[unlikely]] {
      next_row(row, std::forward<Fill>(fill));
    }
    serve(row_.value(static_cast<std::size_t>(column)), out);
  }

 private:
  /// Out of line: SQLite asks for every column, the row is new once in kColumns asks.
  template <typename Fill>
  [[gnu::noinline]] void next_row(std::size_t row, Fill&& fill) {
    if (filled_ && row < row_index_) {
      throw std::logic_error("a fed row's digests: row " + std::to_string(row) +
                             " asked for after row " + std::to_string(row_index_));
    }
    filled_ = false;
    std::forward<Fill>(fill)(row_);
    if (row_.size() != kColumns) {
      throw std::logic_error("a fed row's digests: " + std::to_string(row_.size()) + " values of " +
                             std::to_string(kColumns) + " columns");
    }
    row_.digest(digester_);
    row_index_ = row;
    filled_ = true;
  }

  /// The row's texts and blobs are kept (or outlive it) until the next row is filled, which
  /// SQLite asks for only after it has stored this one: not copied.
  static void serve(const mapcheck::RowValue& value, sqlite3_context* out) {
    static constexpr char kNoBytes = 0;  // a null data pointer would be NULL, not empty
    const char* bytes = value.bytes.empty() ? &kNoBytes : value.bytes.data();
    const int size = static_cast<int>(value.bytes.size());
    switch (value.type) {
      case mapcheck::RowValue::Type::null:
        return;
      case mapcheck::RowValue::Type::integer:
        return sqlite3_result_int64(out, value.integer);
      case mapcheck::RowValue::Type::real:
        return sqlite3_result_double(out, value.real);
      case mapcheck::RowValue::Type::text:
        return sqlite3_result_text(out, bytes, size, SQLITE_STATIC);
      case mapcheck::RowValue::Type::blob:
        return sqlite3_result_blob(out, bytes, size, SQLITE_STATIC);
    }
  }

  mapcheck::ColumnsDigester& digester_;
  DigestedRow<kColumns> row_;
  std::size_t row_index_ = 0;
  bool filled_ = false;
};

}  // namespace roadcross::preprocess
