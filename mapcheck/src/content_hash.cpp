#include "roadcross/mapcheck/content_hash.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <future>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "roadcross/mapcheck/bulk_io_vfs.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross::mapcheck {

namespace {

using Digest = std::array<std::uint8_t, 32>;

/// The 8 bytes of `value`, most significant first.
std::array<std::uint8_t, 8> big_endian(std::uint64_t value) {
  if constexpr (std::endian::native == std::endian::little) value = __builtin_bswap64(value);
  return std::bit_cast<std::array<std::uint8_t, 8>>(value);
}

/// An incremental SHA-256 (OpenSSL's EVP interface). The bytes are gathered in a buffer and
/// handed to OpenSSL kBufferBytes at a time: the digest of the same byte stream, but a value of
/// 9 bytes no longer costs an EVP call of its own (each call's overhead is many times the
/// hashing of 9 bytes, and a map has tens of millions of values).
class Sha256 {
 public:
  Sha256() : context_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    if (!context_ || EVP_DigestInit_ex(context_.get(), EVP_sha256(), nullptr) != 1) {
      throw std::runtime_error("OpenSSL: cannot initialise SHA-256");
    }
  }
  void update(const void* bytes, std::size_t size) {
    if (size == 0) return;  // (an empty text's or blob's data may be null: no memcpy from it)
    if (used_ + size > kBufferBytes) flush();
    if (size >= kBufferBytes) {
      hash(bytes, size);  // a large value goes straight through
      return;
    }
    // (A plain copy: a value is a few bytes, and this runs for each of tens of millions.)
    std::memcpy(buffer_.get() + used_, bytes, size);
    used_ += size;
  }
  void update_byte(std::uint8_t byte) { update(&byte, 1); }
  void update_u64(std::uint64_t value) {
    const std::array<std::uint8_t, 8> bytes = big_endian(value);
    update(bytes.data(), bytes.size());
  }
  /// Length-prefixed bytes: 8-byte big-endian length, then the bytes.
  void update_sized(std::string_view bytes) {
    update_u64(bytes.size());
    update(bytes.data(), bytes.size());
  }
  Digest finish() {
    flush();
    Digest out{};
    unsigned int size = 0;
    if (EVP_DigestFinal_ex(context_.get(), out.data(), &size) != 1 || size != out.size()) {
      throw std::runtime_error("OpenSSL: SHA-256 final failed");
    }
    return out;
  }

 private:
  static constexpr std::size_t kBufferBytes = 16 * 1024;
  void flush() {
    hash(buffer_.get(), used_);
    used_ = 0;
  }
  void hash(const void* bytes, std::size_t size) {
    if (size > 0 && EVP_DigestUpdate(context_.get(), bytes, size) != 1) {
      throw std::runtime_error("OpenSSL: SHA-256 update failed");
    }
  }
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context_;
  std::unique_ptr<std::uint8_t[]> buffer_ =
      std::make_unique_for_overwrite<std::uint8_t[]>(kBufferBytes);
  std::size_t used_ = 0;
};

std::string hex(const Digest& digest) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(digest.size() * 2);
  for (std::uint8_t byte : digest) {
    out += kDigits[byte >> 4];
    out += kDigits[byte & 0x0f];
  }
  return out;
}

/// A type byte and an 8-byte big-endian payload, in one update.
void update_fixed(Sha256& sha, char type, std::uint64_t payload) {
  std::array<std::uint8_t, 9> bytes;
  bytes[0] = static_cast<std::uint8_t>(type);
  const std::array<std::uint8_t, 8> payload_bytes = big_endian(payload);
  std::memcpy(bytes.data() + 1, payload_bytes.data(), payload_bytes.size());
  sha.update(bytes.data(), bytes.size());
}

// One value in the documented encoding: a type byte, then a fixed-size or length-prefixed
// payload. The file's reader (hash_value) and the writer's ColumnsDigester both go through these.
void hash_null(Sha256& sha) {
  sha.update_byte('N');
}
void hash_integer(Sha256& sha, std::int64_t value) {
  update_fixed(sha, 'I', static_cast<std::uint64_t>(value));
}
void hash_real(Sha256& sha, double value) {
  update_fixed(sha, 'R', std::bit_cast<std::uint64_t>(value));
}
void hash_bytes(Sha256& sha, char type, std::string_view bytes) {
  sha.update_byte(static_cast<std::uint8_t>(type));
  sha.update_sized(bytes);
}

/// Feeds one SQLite value. Read through sqlite3_column_value: one call into the statement a value
/// instead of two (type, then the value), each of which takes and leaves the connection's mutex
/// and checks for a failed allocation; the value's accessors do neither. (Safe here: one thread
/// uses the statement's connection.)
void hash_value(Sha256& sha, sqlite3_stmt* row, int column) {
  sqlite3_value* value = sqlite3_column_value(row, column);
  switch (sqlite3_value_type(value)) {
    case SQLITE_NULL:
      return hash_null(sha);
    case SQLITE_INTEGER:
      return hash_integer(sha, sqlite3_value_int64(value));
    case SQLITE_FLOAT:
      return hash_real(sha, sqlite3_value_double(value));
    case SQLITE_TEXT: {
      const auto* text = reinterpret_cast<const char*>(sqlite3_value_text(value));
      return hash_bytes(sha, 'T', {text, static_cast<std::size_t>(sqlite3_value_bytes(value))});
    }
    default: {  // SQLITE_BLOB
      const auto* blob = static_cast<const char*>(sqlite3_value_blob(value));
      return hash_bytes(sha, 'B', {blob, static_cast<std::size_t>(sqlite3_value_bytes(value))});
    }
  }
}

bool has_table(sqlite3* db, std::string_view table) {
  sqlite::Statement query(db,
                          "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1");
  query.bind(1, table);
  query.step();
  return query.column_int64(0) > 0;
}

std::vector<std::string> column_names(sqlite3* db, std::string_view table) {
  std::vector<std::string> names;
  for (DeclaredColumn& column : declared_columns(db, table))
    names.push_back(std::move(column.name));
  return names;
}

std::string quoted_identifier(std::string_view name) {
  std::string out = "\"";
  for (char c : name) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

/// A hashed table: its name, the row filter and the row order.
struct HashedTable {
  std::string_view name;
  std::string where;
  std::string_view order_by;
};

std::vector<HashedTable> hashed_tables() {
  // The metadata rows that hold the digests themselves are not part of what they digest.
  const std::string own_rows = "WHERE key <> '" + std::string(schema::meta::kMapId) +
                               "' AND substr(key, 1, " +
                               std::to_string(schema::meta::kContentDigestPrefix.size()) +
                               ") <> '" + std::string(schema::meta::kContentDigestPrefix) + "'";
  return {
      {schema::kMetadataTable, own_rows, "key"},    {schema::kSegmentsTable, "", "fid"},
      {schema::kCrossingsTable, "", "fid"},         {"terrain", "", "id"},
      {"gpkg_2d_gridded_tile_ancillary", "", "id"},
  };
}

/// The digests of columns [first, last) of `table` (`columns`: all its columns, in order), in
/// one pass over its rows.
std::vector<Digest> digest_columns(sqlite3* db, const HashedTable& table,
                                   const std::vector<std::string>& columns, std::size_t first,
                                   std::size_t last) {
  std::string select = "SELECT ";
  for (std::size_t i = first; i < last; ++i) {
    select += (i > first ? ", " : "") + quoted_identifier(columns[i]);
  }
  select += " FROM " + quoted_identifier(table.name) + " " + table.where + " ORDER BY " +
            std::string(table.order_by);
  std::vector<Sha256> column_hashes(last - first);
  sqlite::Statement rows(db, select);
  while (rows.step()) {
    sqlite3_stmt* row = rows.handle();
    for (std::size_t i = 0; i < column_hashes.size(); ++i) {
      hash_value(column_hashes[i], row, static_cast<int>(i));
    }
  }
  std::vector<Digest> digests;
  digests.reserve(column_hashes.size());
  for (Sha256& hash : column_hashes) digests.push_back(hash.finish());
  return digests;
}

/// A hashed table that is present, with its columns and their digests (filled by the shares).
struct TableDigests {
  HashedTable table;
  std::vector<std::string> columns;
  std::vector<Digest> digests;
  /// Filled from a WrittenTableDigest: not read from the file.
  bool written = false;
};

/// The hashed tables present in `db`; throws when the metadata or segments table is missing.
std::vector<TableDigests> present_tables(sqlite3* db) {
  for (std::string_view required : {schema::kMetadataTable, schema::kSegmentsTable}) {
    if (!has_table(db, required)) {
      throw std::runtime_error("no table " + std::string(required) + ": not a roadcross map");
    }
  }
  std::vector<TableDigests> tables;
  for (const HashedTable& table : hashed_tables()) {
    if (!has_table(db, table.name)) continue;
    std::vector<std::string> columns = column_names(db, table.name);
    std::vector<Digest> digests(columns.size());
    tables.push_back({table, std::move(columns), std::move(digests)});
  }
  return tables;
}

/// Columns [first, last) of a table's `column_count` in share `share` of `shares`: contiguous
/// runs of nearly equal length, so that each share reads every row but decodes only its columns.
std::pair<std::size_t, std::size_t> share_of(std::size_t column_count, std::size_t share,
                                             std::size_t shares) {
  return {column_count * share / shares, column_count * (share + 1) / shares};
}

/// Hashes share `share` of `shares` of every table's columns into `tables`.
void digest_share(sqlite3* db, std::vector<TableDigests>& tables, std::size_t share,
                  std::size_t shares) {
  for (TableDigests& each : tables) {
    if (each.written) continue;
    const auto [first, last] = share_of(each.columns.size(), share, shares);
    if (first == last) continue;
    std::vector<Digest> digests = digest_columns(db, each.table, each.columns, first, last);
    std::copy(digests.begin(), digests.end(), each.digests.begin() + static_cast<long>(first));
  }
}

/// The ContentDigest of the filled `tables`: the columns in order and the map_id over them.
ContentDigest assemble(const std::vector<TableDigests>& tables) {
  ContentDigest content;
  Sha256 map_id;
  for (const TableDigests& each : tables) {
    for (std::size_t i = 0; i < each.columns.size(); ++i) {
      content.columns.push_back(
          {std::string(each.table.name), each.columns[i], hex(each.digests[i])});
      map_id.update_sized(each.table.name);
      map_id.update_sized(each.columns[i]);
      map_id.update(each.digests[i].data(), each.digests[i].size());
    }
  }
  content.map_id = hex(map_id.finish());
  return content;
}

}  // namespace

std::string ColumnDigest::metadata_key() const {
  return std::string(schema::meta::kContentDigestPrefix) + table + "." + column;
}

bool is_map_id(const std::string& text) {
  if (text.size() != 64) return false;
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

ContentDigest compute_content_digest(sqlite3* db) {
  std::vector<TableDigests> tables = present_tables(db);
  digest_share(db, tables, 0, 1);
  return assemble(tables);
}

std::vector<DeclaredColumn> declared_columns(sqlite3* db, std::string_view table) {
  sqlite::Statement info(db, "SELECT name, type, pk FROM pragma_table_info(?1) ORDER BY cid");
  info.bind(1, table);
  std::vector<DeclaredColumn> columns;
  int key_columns = 0;
  std::size_t key = 0;
  while (info.step()) {
    if (info.column_int64(2) > 0) {
      ++key_columns;
      key = columns.size();
    }
    columns.push_back({info.column_text(0), info.column_text(1), false});
  }
  if (columns.empty()) throw std::runtime_error("no table " + std::string(table));
  // A single-column INTEGER PRIMARY KEY (that spelling exactly, any case) is the rowid.
  if (key_columns == 1) {
    std::string type = columns[key].declared_type;
    std::transform(type.begin(), type.end(), type.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    columns[key].rowid = type == "INTEGER";
  }
  return columns;
}

namespace {

/// A column's type affinity (sqlite.org/datatype3.html, 3.1).
enum class Affinity { integer, text, blob, real, numeric };

Affinity affinity_of(std::string declared_type) {
  std::transform(declared_type.begin(), declared_type.end(), declared_type.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  const auto has = [&](std::string_view part) {
    return declared_type.find(part) != std::string::npos;
  };
  if (has("INT")) return Affinity::integer;
  if (has("CHAR") || has("CLOB") || has("TEXT")) return Affinity::text;
  if (has("BLOB") || declared_type.empty()) return Affinity::blob;
  if (has("REAL") || has("FLOA") || has("DOUB")) return Affinity::real;
  return Affinity::numeric;
}

/// The integer SQLite turns a REAL into in an INTEGER, NUMERIC or REAL column
/// (sqlite3VdbeIntegerAffinity): the value when it is integral and strictly inside the int64
/// range. -0.0 gives 0.
std::optional<std::int64_t> integral(double value) {
  constexpr double kTwoTo63 = 9223372036854775808.0;
  if (!(value > -kTwoTo63 && value < kTwoTo63) || std::trunc(value) != value) return std::nullopt;
  return static_cast<std::int64_t>(value);
}

Digest digest_of_hex(const std::string& hex_digits) {
  Digest digest{};
  if (!is_map_id(hex_digits)) throw std::logic_error("not a SHA-256 digest: " + hex_digits);
  const auto nibble = [](char c) { return c <= '9' ? c - '0' : c - 'a' + 10; };
  for (std::size_t i = 0; i < digest.size(); ++i) {
    digest[i] =
        static_cast<std::uint8_t>(nibble(hex_digits[2 * i]) * 16 + nibble(hex_digits[2 * i + 1]));
  }
  return digest;
}

}  // namespace

struct ColumnsDigester::State {
  std::string table;
  std::vector<DeclaredColumn> columns;
  std::vector<Affinity> affinities;
  std::vector<Sha256> hashes;
  std::uint64_t rows = 0;
  std::optional<std::int64_t> first_rowid, last_rowid;

  [[noreturn]] void refuse(std::size_t index, std::string_view what) const {
    throw std::logic_error("ColumnsDigester: " + std::string(what) + " for " + table + "." +
                           columns[index].name + " (" + columns[index].declared_type + "), row " +
                           std::to_string(rows + 1) +
                           ": SQLite would not store it as given; the writer must not produce it");
  }
  /// An INTEGER value as stored in column `index` (after its affinity).
  void stored_integer(std::size_t index, std::int64_t value) {
    if (columns[index].rowid) {
      if (last_rowid && value <= *last_rowid) refuse(index, "a rowid not above the previous");
      if (!first_rowid) first_rowid = value;
      last_rowid = value;
    }
    hash_integer(hashes[index], value);
  }
  void integer(std::size_t index, std::int64_t value) {
    switch (affinities[index]) {
      case Affinity::text:
        refuse(index, "an INTEGER");
      case Affinity::real:
        return hash_real(hashes[index], static_cast<double>(value));
      default:
        return stored_integer(index, value);
    }
  }
  void real(std::size_t index, double value) {
    // sqlite3_result_double and sqlite3_bind_double store a NaN as NULL.
    if (std::isnan(value)) return null(index);
    const Affinity affinity = affinities[index];
    if (affinity == Affinity::text) refuse(index, "a REAL");
    if (affinity == Affinity::blob) return hash_real(hashes[index], value);
    const std::optional<std::int64_t> whole = integral(value);
    if (!whole) return hash_real(hashes[index], value);
    if (affinity == Affinity::real) return hash_real(hashes[index], static_cast<double>(*whole));
    stored_integer(index, *whole);
  }
  void null(std::size_t index) {
    if (columns[index].rowid) refuse(index, "a NULL rowid");
    hash_null(hashes[index]);
  }
  void text(std::size_t index, std::string_view value) {
    const Affinity affinity = affinities[index];
    if (affinity != Affinity::text && affinity != Affinity::blob) refuse(index, "a TEXT");
    hash_bytes(hashes[index], 'T', value);
  }
  void blob(std::size_t index, std::string_view bytes) {
    if (columns[index].rowid) refuse(index, "a BLOB rowid");
    hash_bytes(hashes[index], 'B', bytes);
  }
};

ColumnsDigester::ColumnsDigester(std::string table, std::vector<DeclaredColumn> columns)
    : state_(std::make_unique<State>()) {
  state_->table = std::move(table);
  for (const DeclaredColumn& column : columns) {
    state_->affinities.push_back(affinity_of(column.declared_type));
  }
  state_->columns = std::move(columns);
  state_->hashes.resize(state_->columns.size());
}

ColumnsDigester::ColumnsDigester(ColumnsDigester&&) noexcept = default;
ColumnsDigester& ColumnsDigester::operator=(ColumnsDigester&&) noexcept = default;
ColumnsDigester::~ColumnsDigester() = default;

void ColumnsDigester::add_row(std::span<const RowValue> row) {
  State& state = *state_;
  if (row.size() != state.columns.size()) {
    throw std::logic_error("ColumnsDigester: " + state.table + " row " +
                           std::to_string(state.rows + 1) + " has " + std::to_string(row.size()) +
                           " values, not " + std::to_string(state.columns.size()));
  }
  for (std::size_t i = 0; i < row.size(); ++i) {
    const RowValue& value = row[i];
    switch (value.type) {
      case RowValue::Type::null:
        state.null(i);
        break;
      case RowValue::Type::integer:
        state.integer(i, value.integer);
        break;
      case RowValue::Type::real:
        state.real(i, value.real);
        break;
      case RowValue::Type::text:
        state.text(i, value.bytes);
        break;
      case RowValue::Type::blob:
        state.blob(i, value.bytes);
        break;
    }
  }
  ++state.rows;
}

std::uint64_t ColumnsDigester::rows() const noexcept {
  return state_->rows;
}

WrittenTableDigest ColumnsDigester::finish() {
  State state = std::move(*state_);
  state_.reset();
  WrittenTableDigest out{state.table, std::move(state.columns), {},
                         state.rows,  state.first_rowid,        state.last_rowid};
  for (std::size_t i = 0; i < out.columns.size(); ++i) {
    out.digests.push_back({out.table, out.columns[i].name, hex(state.hashes[i].finish())});
  }
  return out;
}

namespace {

/// Takes `written`'s digests for its table in `tables`, after checking that the file's table is
/// the one they were computed for: the same columns, row count and first and last rowid.
void use_written(sqlite3* db, std::vector<TableDigests>& tables,
                 const WrittenTableDigest& written) {
  const auto fail = [&](const std::string& what) {
    throw std::logic_error("the digests of the rows written into " + written.table +
                           " do not fit the file: " + what);
  };
  const auto table = std::find_if(tables.begin(), tables.end(), [&](const TableDigests& each) {
    return each.table.name == written.table;
  });
  if (table == tables.end()) fail("no such hashed table in the file");
  if (declared_columns(db, written.table) != written.columns) fail("other columns");
  if (written.digests.size() != written.columns.size()) fail("not one digest per column");
  const auto rowid = std::find_if(written.columns.begin(), written.columns.end(),
                                  [](const DeclaredColumn& column) { return column.rowid; });
  // The first and last rowid: two index lookups. (A count(*) would walk every page of the
  // table, seconds at 200x; that every row went in, the writer checks: insert_rows.)
  const std::string from = " FROM " + quoted_identifier(written.table) + ")";
  if (written.rows == 0) {
    sqlite::Statement any(db, "SELECT EXISTS (SELECT 1" + from);
    any.step();
    if (any.column_int64(0) != 0) fail("rows where none were digested");
  } else if (rowid != written.columns.end()) {
    const std::string name = quoted_identifier(rowid->name);
    sqlite::Statement ends(
        db, "SELECT (SELECT min(" + name + ")" + from + ", (SELECT max(" + name + ")" + from);
    ends.step();
    if (ends.column_int64(0) != written.first_rowid || ends.column_int64(1) != written.last_rowid) {
      fail("other first or last " + rowid->name);
    }
  }
  for (std::size_t i = 0; i < written.digests.size(); ++i) {
    table->digests[i] = digest_of_hex(written.digests[i].sha256_hex);
  }
  table->written = true;
}

ContentDigest content_of(const std::string& path, unsigned threads,
                         const WrittenTableDigest* written) {
  constexpr int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX;
  // Each connection walks the tables' pages mostly in file order: read ahead, not a page a call.
  const char* vfs = bulk_io_vfs();
  sqlite::Database first(path, flags, vfs);
  std::vector<TableDigests> tables = present_tables(first.handle());
  if (written) use_written(first.handle(), tables, *written);
  const std::size_t shares = std::max(1u, threads);
  // Each share on its own connection and thread; the columns' digests do not depend on which
  // share computed them. std::async's futures wait for their threads if one share throws.
  std::vector<std::future<void>> others;
  for (std::size_t share = 1; share < shares; ++share) {
    others.push_back(std::async(std::launch::async, [&path, &tables, share, shares, vfs] {
      sqlite::Database db(path, flags, vfs);
      digest_share(db.handle(), tables, share, shares);
    }));
  }
  digest_share(first.handle(), tables, 0, shares);
  for (std::future<void>& other : others) other.get();
  return assemble(tables);
}

std::string stamp(const std::string& path, const ContentDigest& content) {
  // One thread uses each connection: no mutex round each sqlite3_column_* call (two a value).
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX);
  // No journal and no fsync of its own: the file is the build's private temporary one, removed
  // on any failure and made durable (fsync) before it is renamed into place.
  db.exec("PRAGMA journal_mode = OFF");
  db.exec("PRAGMA synchronous = OFF");
  db.exec("BEGIN");
  const std::string table(schema::kMetadataTable);
  auto insert = db.prepare("INSERT OR REPLACE INTO " + table + " (key, value) VALUES (?1, ?2)");
  insert.bind(1, schema::meta::kMapId);
  insert.bind(2, content.map_id);
  insert.run();
  for (const ColumnDigest& column : content.columns) {
    insert.bind(1, column.metadata_key());
    insert.bind(2, column.sha256_hex);
    insert.run();
  }
  db.exec("COMMIT");
  return content.map_id;
}

}  // namespace

ContentDigest compute_content_digest(const std::string& path, unsigned threads) {
  return content_of(path, threads, nullptr);
}

std::string stamp_map_id(const std::string& path, unsigned threads) {
  return stamp(path, content_of(path, threads, nullptr));
}

std::string stamp_map_id(const std::string& path, unsigned threads,
                         const WrittenTableDigest& written) {
  return stamp(path, content_of(path, threads, &written));
}

}  // namespace roadcross::mapcheck
