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

#include <string>
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

/// Computes the digests of the map at `path` and stores map_id and the content.* rows in its
/// roadcross_metadata (replacing earlier ones), in one transaction, without a journal or an
/// fsync: for roadcross-build, on its private temporary file. Returns map_id. Throws
/// sqlite::sqlite_error naming the problem. `threads`: as compute_content_digest's; the file must
/// not be open for writing meanwhile.
std::string stamp_map_id(const std::string& path, unsigned threads = 1);

/// True when `text` looks like a map_id: 64 lower-case hex digits.
bool is_map_id(const std::string& text);

}  // namespace roadcross::mapcheck
