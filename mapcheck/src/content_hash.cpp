#include "roadcross/mapcheck/content_hash.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <future>
#include <memory>
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
    buffer_.reserve(kBufferBytes);
  }
  void update(const void* bytes, std::size_t size) {
    if (buffer_.size() + size > kBufferBytes) flush();
    if (size >= kBufferBytes) {
      hash(bytes, size);  // a large value goes straight through
      return;
    }
    const auto* first = static_cast<const char*>(bytes);
    buffer_.append(first, size);
  }
  void update_byte(std::uint8_t byte) { update(&byte, 1); }
  void update_u64(std::uint64_t value) {
    std::array<std::uint8_t, 8> big_endian{};
    for (int i = 7; i >= 0; --i, value >>= 8)
      big_endian[static_cast<std::size_t>(i)] = value & 0xff;
    update(big_endian.data(), big_endian.size());
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
    hash(buffer_.data(), buffer_.size());
    buffer_.clear();
  }
  void hash(const void* bytes, std::size_t size) {
    if (size > 0 && EVP_DigestUpdate(context_.get(), bytes, size) != 1) {
      throw std::runtime_error("OpenSSL: SHA-256 update failed");
    }
  }
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context_;
  std::string buffer_;
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
  std::array<std::uint8_t, 9> bytes{};
  bytes[0] = static_cast<std::uint8_t>(type);
  for (std::size_t i = 8; i >= 1; --i, payload >>= 8) bytes[i] = payload & 0xff;
  sha.update(bytes.data(), bytes.size());
}

/// Feeds one SQLite value in the documented encoding (type byte, then a fixed-size or
/// length-prefixed payload). Read through sqlite3_column_value: one call into the statement
/// a value instead of two (type, then the value), each of which takes and leaves the
/// connection's mutex and checks for a failed allocation; the value's accessors do neither.
/// (Safe here: one thread uses the statement's connection.)
void hash_value(Sha256& sha, sqlite3_stmt* row, int column) {
  sqlite3_value* value = sqlite3_column_value(row, column);
  switch (sqlite3_value_type(value)) {
    case SQLITE_NULL:
      sha.update_byte('N');
      break;
    case SQLITE_INTEGER:
      update_fixed(sha, 'I', static_cast<std::uint64_t>(sqlite3_value_int64(value)));
      break;
    case SQLITE_FLOAT:
      update_fixed(sha, 'R', std::bit_cast<std::uint64_t>(sqlite3_value_double(value)));
      break;
    case SQLITE_TEXT: {
      const auto* text = reinterpret_cast<const char*>(sqlite3_value_text(value));
      sha.update_byte('T');
      sha.update_sized({text, static_cast<std::size_t>(sqlite3_value_bytes(value))});
      break;
    }
    default: {  // SQLITE_BLOB
      const auto* blob = static_cast<const char*>(sqlite3_value_blob(value));
      sha.update_byte('B');
      sha.update_sized({blob, static_cast<std::size_t>(sqlite3_value_bytes(value))});
      break;
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
  sqlite::Statement info(db, "SELECT name FROM pragma_table_info(?1) ORDER BY cid");
  info.bind(1, table);
  std::vector<std::string> names;
  while (info.step()) names.push_back(info.column_text(0));
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

ContentDigest compute_content_digest(const std::string& path, unsigned threads) {
  const int flags = SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX;
  // Each connection walks the tables' pages mostly in file order: read ahead, not a page a call.
  const char* vfs = bulk_io_vfs();
  sqlite::Database first(path, flags, vfs);
  std::vector<TableDigests> tables = present_tables(first.handle());
  const std::size_t shares = std::max(1u, threads);
  // Each share on its own connection and thread; the columns' digests do not depend on which
  // share computed them. std::async's futures wait for their threads if one share throws.
  std::vector<std::future<void>> others;
  for (std::size_t share = 1; share < shares; ++share) {
    others.push_back(std::async(std::launch::async, [&path, &tables, share, shares, flags, vfs] {
      sqlite::Database db(path, flags, vfs);
      digest_share(db.handle(), tables, share, shares);
    }));
  }
  digest_share(first.handle(), tables, 0, shares);
  for (std::future<void>& other : others) other.get();
  return assemble(tables);
}

std::string stamp_map_id(const std::string& path, unsigned threads) {
  const ContentDigest content = compute_content_digest(path, threads);
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

}  // namespace roadcross::mapcheck
