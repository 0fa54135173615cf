// The identity of a roadcross map: SHA-256 digests of its content, computed in one place for
// the writer (roadcross-build stamps them into roadcross_metadata) and for `roadcross verify`.
// The encoding is specified in docs/embedding.md ("The map's identity"); in short:
//
//  - hashed tables, in this order, those present: roadcross_metadata (without the map_id and
//    content.* rows, ordered by key), segments, crossings (ordered by fid), terrain and
//    gpkg_2d_gridded_tile_ancillary (the elevation grid, ordered by id);
//  - every column (PRAGMA table_info order) gets its own digest: SHA-256 over its values in row
//    order, each value a type byte and a fixed encoding: 'N' (NULL), 'I' + 8-byte big-endian
//    two's complement, 'R' + the 8 bytes of the IEEE-754 double big-endian, 'T' / 'B' + 8-byte
//    big-endian byte length + the UTF-8 text / blob bytes;
//  - map_id = SHA-256 over, for every column in order: length-prefixed table name,
//    length-prefixed column name, the column's 32-byte digest. Written as 64 lower-case hex.
//
// The runtime library does not link this (nor libcrypto): it only reads map_id.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

struct sqlite3;

namespace roadcross::mapcheck {

/// One hashed column: "<table>.<column>" and its SHA-256 as 64 lower-case hex digits.
struct ColumnDigest {
  std::string table;
  std::string column;
  std::string sha256_hex;
  /// The metadata key the writer stores the digest under: "content.<table>.<column>".
  std::string metadata_key() const;
};

/// The content of a map: every hashed column's digest and the map_id made of them.
struct ContentDigest {
  std::vector<ColumnDigest> columns;
  std::string map_id;
};

/// Computes the digests of the open database `db` (read only). Throws sqlite::sqlite_error on a
/// read error and std::runtime_error when the segments or metadata table is missing.
ContentDigest compute_content_digest(sqlite3* db);

/// The same digests of the map at `path`, on `threads` threads (0 counts as 1), each with its own
/// read-only connection and a share of every table's columns: SHA-256 is sequential along a
/// column, so the columns are what divides. Throws as above.
ContentDigest compute_content_digest(const std::string& path, unsigned threads);

/// A column as the file declares it (PRAGMA table_info): name, declared type, and whether it is
/// the table's rowid (its INTEGER PRIMARY KEY).
struct DeclaredColumn {
  std::string name;
  std::string declared_type;
  bool rowid = false;
  bool operator==(const DeclaredColumn&) const = default;
};

/// The columns of `table` in `db`, in order; throws std::runtime_error when there is no such
/// table.
std::vector<DeclaredColumn> declared_columns(sqlite3* db, std::string_view table);

/// One table's column digests computed from the values written into it (ColumnsDigester), in
/// place of reading the table back: what stamp_map_id checks against the file before using them.
struct WrittenTableDigest {
  std::string table;
  std::vector<DeclaredColumn> columns;
  /// One per column, in order.
  std::vector<ColumnDigest> digests;
  std::uint64_t rows = 0;
  /// The rowid column's first and last value (ascending), when the table has one and rows > 0.
  std::optional<std::int64_t> first_rowid, last_rowid;
};

/// One value of a row for ColumnsDigester::add_row, as a writer hands it to SQLite: its type
/// and content (text and blob bytes viewed, not copied).
struct RowValue {
  enum class Type : std::uint8_t { null, integer, real, text, blob };
  Type type = Type::null;
  std::int64_t integer = 0;
  double real = 0.0;
  std::string_view bytes;

  static RowValue of_integer(std::int64_t value) { return {Type::integer, value, 0.0, {}}; }
  static RowValue of_real(double value) { return {Type::real, 0, value, {}}; }
  static RowValue of_text(std::string_view text) { return {Type::text, 0, 0.0, text}; }
  static RowValue of_blob(std::string_view bytes) { return {Type::blob, 0, 0.0, bytes}; }
};

/// The column digests of one hashed table computed from the rows as they are written, fed one
/// row at a time (one value per column, in column order), in the table's hashed order (segments
/// and crossings: ascending fid), from one thread; finish() at the end.
///
/// The digests are of what a reader gets back from the file, so each value is taken through the
/// column's affinity (from its declared type, SQLite's rules: sqlite.org/datatype3.html) as
/// SQLite stores it:
///  - a REAL NaN is stored as NULL (whatever the column);
///  - in an INTEGER or NUMERIC column (BOOLEAN, LINESTRING, ... are NUMERIC), a REAL with an
///    integral value in (-2^63, 2^63) becomes that INTEGER;
///  - in a REAL column an INTEGER reads back as that REAL, and a REAL with an integral value in
///    (-2^63, 2^63) is stored as an integer and reads back as REAL: the same number, except that
///    -0.0 comes back as +0.0;
///  - a column of no (or BLOB) affinity, NULLs and BLOBs: unchanged.
/// Conversions between TEXT and numbers (a numeric text in a numeric column, a number in a TEXT
/// column) and a rowid that is NULL (SQLite assigns one), not an integer or not above the previous
/// row's throw std::logic_error instead of being mirrored: the writers never produce them. So
/// does a row with more or fewer values than columns.
class ColumnsDigester {
 public:
  ColumnsDigester(std::string table, std::vector<DeclaredColumn> columns);
  ColumnsDigester(ColumnsDigester&&) noexcept;
  ColumnsDigester& operator=(ColumnsDigester&&) noexcept;
  ~ColumnsDigester();

  /// The next row, one value per column. After an exception the digests are of no use.
  void add_row(std::span<const RowValue> row);

  std::uint64_t rows() const noexcept;
  /// The digests of the rows so far; the digester is spent.
  WrittenTableDigest finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// Computes the digests of the map at `path` and stores map_id and the content.* rows in its
/// roadcross_metadata (replacing earlier ones), in one transaction, without a journal or an
/// fsync: for roadcross-build, on its private temporary file. Returns map_id. Throws
/// sqlite::sqlite_error naming the problem. `threads`: as compute_content_digest's; the file must
/// not be open for writing meanwhile.
std::string stamp_map_id(const std::string& path, unsigned threads = 1);

/// The same, with the digests of `written.table` taken from `written` instead of read back: only
/// the other tables are read from the file. Before they are used, the file's table must have the
/// same columns (names, declared types, rowid) and the same first and last rowid; otherwise
/// throws std::logic_error and stamps nothing. Its rows are not counted (that walks every page
/// of the table): the writer makes sure each row it digested went in (insert_rows checks).
std::string stamp_map_id(const std::string& path, unsigned threads,
                         const WrittenTableDigest& written);

/// True when `text` looks like a map_id: 64 lower-case hex digits.
bool is_map_id(const std::string& text);

}  // namespace roadcross::mapcheck
