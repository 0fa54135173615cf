// compute_content_digest(): the documented encoding (docs/embedding.md, "The map's identity"),
// checked against byte streams written out here by hand, and the same digests on any number of
// threads (each thread a share of every table's columns) as on one connection.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/preprocess/common/sha256.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace mc = roadcross::mapcheck;
namespace sqlite = roadcross::sqlite;

namespace {

std::string big_endian(std::uint64_t value) {
  std::string out(8, '\0');
  for (int i = 7; i >= 0; --i, value >>= 8) out[static_cast<std::size_t>(i)] = char(value & 0xff);
  return out;
}

std::string sha256_hex(const std::string& bytes) {
  roadcross::preprocess::Sha256 sha;
  sha.update(bytes.data(), bytes.size());
  return sha.hex_digest();
}

std::string sized(const std::string& bytes) {
  return big_endian(bytes.size()) + bytes;
}

/// A file with the two tables a map needs: metadata (two rows hashed, the map_id row not) and
/// three segments whose columns hold every value type.
std::string small_map(const std::string& name) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::filesystem::remove(path);
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE TABLE roadcross_metadata (key TEXT PRIMARY KEY, value TEXT)");
  db.exec("INSERT INTO roadcross_metadata VALUES ('b', 'x'), ('a', 'yz'), ('map_id', 'old')");
  db.exec("CREATE TABLE segments (fid INTEGER PRIMARY KEY, n INTEGER, r REAL, t TEXT, g BLOB)");
  // Inserted out of fid order: the digest follows fid.
  db.exec("INSERT INTO segments VALUES (2, -1, NULL, 'ab', x'0102')");
  db.exec("INSERT INTO segments VALUES (1, 7, 0.5, NULL, NULL)");
  db.exec("INSERT INTO segments VALUES (3, NULL, -2.0, '', x'')");
  return path;
}

/// One value's bytes: its type byte, then `payload`. (Appended, not "T" + ...: GCC 12 warns
/// falsely, -Wrestrict.)
std::string value(char type, const std::string& payload = "") {
  std::string out(1, type);
  out += payload;
  return out;
}

std::string integer(std::uint64_t bits) {
  return value('I', big_endian(bits));
}
std::string real(double number) {
  return value('R', big_endian(std::bit_cast<std::uint64_t>(number)));
}
std::string text(const std::string& bytes) {
  return value('T', sized(bytes));
}
std::string blob(const std::string& bytes) {
  return value('B', sized(bytes));
}
const std::string kNull = value('N');

TEST(ContentHash, DigestsAreTheDocumentedByteStreams) {
  const std::string path = small_map("content_hash_small.gpkg");
  const mc::ContentDigest content = mc::compute_content_digest(path, 2);
  const std::vector<std::pair<std::string, std::string>> expected_streams = {
      {"roadcross_metadata.key", text("a") + text("b")},
      {"roadcross_metadata.value", text("yz") + text("x")},
      {"segments.fid", integer(1) + integer(2) + integer(3)},
      {"segments.n", integer(7) + integer(~std::uint64_t{0}) + kNull},
      {"segments.r", real(0.5) + kNull + real(-2.0)},
      {"segments.t", kNull + text("ab") + text("")},
      {"segments.g", kNull + blob("\x01\x02") + blob("")},
  };
  ASSERT_EQ(content.columns.size(), expected_streams.size());
  std::string map_id_stream;
  for (std::size_t i = 0; i < expected_streams.size(); ++i) {
    const mc::ColumnDigest& column = content.columns[i];
    EXPECT_EQ(column.table + "." + column.column, expected_streams[i].first);
    const std::string digest_hex = sha256_hex(expected_streams[i].second);
    EXPECT_EQ(column.sha256_hex, digest_hex) << expected_streams[i].first;
    std::string digest;
    for (std::size_t k = 0; k < digest_hex.size(); k += 2) {
      digest += char(std::stoi(digest_hex.substr(k, 2), nullptr, 16));
    }
    map_id_stream += sized(column.table);
    map_id_stream += sized(column.column);
    map_id_stream += digest;
  }
  EXPECT_EQ(content.map_id, sha256_hex(map_id_stream));
  std::filesystem::remove(path);
}

TEST(ContentHash, AnyNumberOfThreadsGivesTheOneConnectionDigests) {
  const std::string path = small_map("content_hash_threads.gpkg");
  {
    // More rows and columns than threads, and a crossings table (hashed after segments).
    sqlite::Database db(path, SQLITE_OPEN_READWRITE);
    db.exec("CREATE TABLE crossings (fid INTEGER PRIMARY KEY, kind TEXT)");
    db.exec("BEGIN");
    for (int fid = 4; fid < 3000; ++fid) {
      db.exec("INSERT INTO segments VALUES (" + std::to_string(fid) + ", " +
              std::to_string(fid * 3) + ", " + std::to_string(fid) + ".25, 't" +
              std::to_string(fid % 7) + "', randomblob(" + std::to_string(fid % 13) + "))");
    }
    db.exec("INSERT INTO crossings VALUES (1, 'zebra'), (2, NULL)");
    db.exec("COMMIT");
  }
  sqlite::Database db(path, SQLITE_OPEN_READONLY);
  const mc::ContentDigest one = mc::compute_content_digest(db.handle());
  EXPECT_EQ(one.columns.size(), 9u);
  // 0 counts as 1; 9 threads leave every share one column, 12 some shares none.
  for (unsigned threads : {0u, 1u, 2u, 3u, 4u, 9u, 12u}) {
    const mc::ContentDigest many = mc::compute_content_digest(path, threads);
    EXPECT_EQ(many.map_id, one.map_id) << threads << " threads";
    ASSERT_EQ(many.columns.size(), one.columns.size());
    for (std::size_t i = 0; i < one.columns.size(); ++i) {
      EXPECT_EQ(many.columns[i].column, one.columns[i].column);
      EXPECT_EQ(many.columns[i].sha256_hex, one.columns[i].sha256_hex)
          << one.columns[i].table << "." << one.columns[i].column << ", " << threads << " threads";
    }
  }
  std::filesystem::remove(path);
}

TEST(ContentHash, StampWritesTheMapIdOfTheContent) {
  const std::string path = small_map("content_hash_stamp.gpkg");
  const std::string map_id = mc::stamp_map_id(path, 2);
  {
    sqlite::Database db(path, SQLITE_OPEN_READONLY);
    EXPECT_EQ(mc::compute_content_digest(db.handle()).map_id, map_id);
    auto stored = db.prepare("SELECT value FROM roadcross_metadata WHERE key = 'map_id'");
    ASSERT_TRUE(stored.step());
    EXPECT_EQ(stored.column_text(0), map_id);
  }
  // The stored map_id and content.* rows are not part of what they digest: stamping again
  // gives the same id.
  EXPECT_EQ(mc::stamp_map_id(path, 3), map_id);
  std::filesystem::remove(path);
}

}  // namespace
