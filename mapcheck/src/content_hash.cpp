#include "roadcross/mapcheck/content_hash.hpp"

#include <openssl/evp.h>

#include <array>
#include <bit>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

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

/// Feeds one SQLite value in the documented encoding (type byte, then a fixed-size or
/// length-prefixed payload).
void hash_value(Sha256& sha, sqlite3_stmt* row, int column) {
  switch (sqlite3_column_type(row, column)) {
    case SQLITE_NULL:
      sha.update_byte('N');
      break;
    case SQLITE_INTEGER:
      sha.update_byte('I');
      sha.update_u64(static_cast<std::uint64_t>(sqlite3_column_int64(row, column)));
      break;
    case SQLITE_FLOAT:
      sha.update_byte('R');
      sha.update_u64(std::bit_cast<std::uint64_t>(sqlite3_column_double(row, column)));
      break;
    case SQLITE_TEXT: {
      const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(row, column));
      sha.update_byte('T');
      sha.update_sized({text, static_cast<std::size_t>(sqlite3_column_bytes(row, column))});
      break;
    }
    default: {  // SQLITE_BLOB
      const auto* blob = static_cast<const char*>(sqlite3_column_blob(row, column));
      sha.update_byte('B');
      sha.update_sized({blob, static_cast<std::size_t>(sqlite3_column_bytes(row, column))});
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

/// Appends the digest of every column of `table` to `out`, in one pass over its rows.
void digest_table(sqlite3* db, const HashedTable& table, std::vector<ColumnDigest>& out) {
  const std::vector<std::string> columns = column_names(db, table.name);
  std::string select = "SELECT ";
  for (std::size_t i = 0; i < columns.size(); ++i) {
    select += (i ? ", " : "") + quoted_identifier(columns[i]);
  }
  select += " FROM " + quoted_identifier(table.name) + " " + table.where + " ORDER BY " +
            std::string(table.order_by);
  std::vector<Sha256> column_hashes(columns.size());
  sqlite::Statement rows(db, select);
  while (rows.step()) {
    sqlite3_stmt* row = rows.handle();
    for (std::size_t i = 0; i < columns.size(); ++i) {
      hash_value(column_hashes[i], row, static_cast<int>(i));
    }
  }
  for (std::size_t i = 0; i < columns.size(); ++i) {
    out.push_back({std::string(table.name), columns[i], hex(column_hashes[i].finish())});
  }
}

Digest parse_hex(const std::string& text) {
  Digest out{};
  const auto nibble = [](char c) { return c <= '9' ? c - '0' : c - 'a' + 10; };
  for (std::size_t i = 0; i < out.size(); ++i) {
    out[i] = static_cast<std::uint8_t>(nibble(text[2 * i]) * 16 + nibble(text[2 * i + 1]));
  }
  return out;
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
  for (std::string_view required : {schema::kMetadataTable, schema::kSegmentsTable}) {
    if (!has_table(db, required)) {
      throw std::runtime_error("no table " + std::string(required) + ": not a roadcross map");
    }
  }
  ContentDigest content;
  for (const HashedTable& table : hashed_tables()) {
    if (has_table(db, table.name)) digest_table(db, table, content.columns);
  }
  Sha256 map_id;
  for (const ColumnDigest& column : content.columns) {
    map_id.update_sized(column.table);
    map_id.update_sized(column.column);
    const Digest digest = parse_hex(column.sha256_hex);
    map_id.update(digest.data(), digest.size());
  }
  content.map_id = hex(map_id.finish());
  return content;
}

std::string stamp_map_id(const std::string& path) {
  // One thread uses this connection: no mutex round each sqlite3_column_* call (two a value).
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX);
  const ContentDigest content = compute_content_digest(db.handle());
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
