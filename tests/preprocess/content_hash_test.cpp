// compute_content_digest(): the documented encoding (docs/embedding.md, "The map's identity"),
// checked against byte streams written out here by hand, and the same digests on any number of
// threads (each thread a share of every table's columns) as on one connection.
// ColumnsDigester: the digests of values as they are written equal those read back from a SQLite
// table holding them, through every column affinity; the values SQLite would convert in ways it
// does not mirror are refused; stamp_map_id with a table's written digests checks them against
// the file.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <variant>
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

// A value as a writer hands it to SQLite and to the digester.
struct Blob {
  std::string bytes;
};
using Value = std::variant<std::nullptr_t, std::int64_t, double, std::string, Blob>;

void bind_value(sqlite::Statement& insert, int index, const Value& value) {
  sqlite3_stmt* statement = insert.handle();
  if (const auto* i = std::get_if<std::int64_t>(&value)) {
    sqlite3_bind_int64(statement, index, *i);
  } else if (const auto* r = std::get_if<double>(&value)) {
    sqlite3_bind_double(statement, index, *r);
  } else if (const auto* t = std::get_if<std::string>(&value)) {
    sqlite3_bind_text(statement, index, t->data(), static_cast<int>(t->size()), SQLITE_TRANSIENT);
  } else if (const auto* b = std::get_if<Blob>(&value)) {
    sqlite3_bind_blob(statement, index, b->bytes.data(), static_cast<int>(b->bytes.size()),
                      SQLITE_TRANSIENT);
  } else {
    sqlite3_bind_null(statement, index);
  }
}

/// The value as the digester takes it (viewing the text or blob in `value`).
mc::RowValue row_value(const Value& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) return mc::RowValue::of_integer(*i);
  if (const auto* r = std::get_if<double>(&value)) return mc::RowValue::of_real(*r);
  if (const auto* t = std::get_if<std::string>(&value)) return mc::RowValue::of_text(*t);
  if (const auto* b = std::get_if<Blob>(&value)) return mc::RowValue::of_blob(b->bytes);
  return {};
}

void add_row(mc::ColumnsDigester& digester, const std::vector<Value>& values) {
  std::vector<mc::RowValue> row;
  for (const Value& value : values) row.push_back(row_value(value));
  digester.add_row(row);
}

constexpr std::int64_t kMin = std::numeric_limits<std::int64_t>::min();
constexpr std::int64_t kMax = std::numeric_limits<std::int64_t>::max();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTwoTo63 = 9223372036854775808.0;

/// Every number a writer could hand a numeric column: NULL, integers (negative, the int64
/// extremes), reals (both zeros, NaN, the infinities, integral ones on both sides of the int64
/// range's ends, fractions, the largest integral double below 2^63), and a blob.
std::vector<Value> numbers() {
  return {nullptr,
          std::int64_t{0},
          std::int64_t{-1},
          std::int64_t{7},
          kMin,
          kMax,
          std::int64_t{9007199254740993},  // 2^53 + 1: no double equals it
          0.0,
          -0.0,
          std::nan(""),
          kInf,
          -kInf,
          2.0,
          -3.0,
          0.5,
          -0.25,
          1e300,
          -1e-300,
          kTwoTo63,
          -kTwoTo63,
          std::nextafter(kTwoTo63, 0.0),
          -std::nextafter(kTwoTo63, 0.0),
          4503599627370496.5 - 0.5,  // 2^52
          Blob{"\x01\x02"},
          Blob{""}};
}

/// Text and blobs, for the TEXT columns and those of no (BLOB) affinity: empty, an embedded NUL,
/// UTF-8, numeric-looking text (kept as text there).
std::vector<Value> texts() {
  return {std::string(""),
          std::string("abc"),
          std::string("a\0b", 3),
          std::string("Nov\xc3\xa9"),
          std::string("12"),
          std::string("0.5"),
          nullptr,
          Blob{""},
          Blob{std::string("\0\xff", 2)}};
}

struct TestColumn {
  std::string name, type;
  std::vector<Value> values;  ///< cycled over the rows
};

/// A map file whose segments table has `columns` (after fid, the rowid) and `rows` rows of their
/// values, written with bound parameters; the digester is fed the same values, in fid order.
mc::WrittenTableDigest write_and_digest(const std::string& path,
                                        const std::vector<TestColumn>& columns, std::size_t rows) {
  std::filesystem::remove(path);
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  db.exec("CREATE TABLE roadcross_metadata (key TEXT PRIMARY KEY, value TEXT)");
  db.exec("INSERT INTO roadcross_metadata VALUES ('a', 'b')");
  std::string create = "CREATE TABLE segments (fid INTEGER PRIMARY KEY NOT NULL";
  std::string insert_sql = "INSERT INTO segments VALUES (?";
  for (const TestColumn& column : columns) {
    create += ", " + column.name + " " + column.type;
    insert_sql += ", ?";
  }
  db.exec(create + ")");
  mc::ColumnsDigester digester("segments", mc::declared_columns(db.handle(), "segments"));
  auto insert = db.prepare(insert_sql + ")");
  db.exec("BEGIN");
  for (std::size_t row = 0; row < rows; ++row) {
    const std::int64_t fid = 10 + 3 * static_cast<std::int64_t>(row);  // ascending, with gaps
    std::vector<Value> values = {fid};
    for (const TestColumn& column : columns) {
      values.push_back(column.values[row % column.values.size()]);
    }
    for (std::size_t c = 0; c < values.size(); ++c)
      bind_value(insert, static_cast<int>(c) + 1, values[c]);
    insert.run();
    add_row(digester, values);
  }
  db.exec("COMMIT");
  return digester.finish();
}

/// The written digests of the segments table equal the ones read back from the file.
void expect_digests_of_the_file(const std::string& path, const mc::WrittenTableDigest& written) {
  sqlite::Database db(path, SQLITE_OPEN_READONLY);
  const mc::ContentDigest read = mc::compute_content_digest(db.handle());
  std::size_t compared = 0;
  for (const mc::ColumnDigest& column : read.columns) {
    if (column.table != "segments") continue;
    ASSERT_LT(compared, written.digests.size());
    EXPECT_EQ(written.digests[compared].column, column.column);
    EXPECT_EQ(written.digests[compared].sha256_hex, column.sha256_hex)
        << "segments." << column.column << " (" << written.columns[compared].declared_type << ")";
    ++compared;
  }
  EXPECT_EQ(compared, written.digests.size());
}

TEST(ColumnsDigester, EveryAffinityGivesTheDigestsReadBackFromTheFile) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "columns_digester_affinity.gpkg").string();
  // Each numeric column type once per affinity (INTEGER, REAL, NUMERIC as the schema spells it:
  // BOOLEAN and the geometry type), the TEXT ones, and those of BLOB affinity (no type, BLOB).
  const std::vector<TestColumn> columns = {
      {"i", "INTEGER", numbers()},    {"i2", "INT NOT NULL DEFAULT 0", {std::int64_t{3}, 2.0}},
      {"r", "REAL", numbers()},       {"d", "DOUBLE PRECISION", numbers()},
      {"n", "NUMERIC", numbers()},    {"b", "BOOLEAN", numbers()},
      {"g", "LINESTRING", numbers()}, {"t", "TEXT", texts()},
      {"v", "VARCHAR(9)", texts()},   {"x", "BLOB", numbers()},
      {"u", "", numbers()},           {"u2", "", texts()},
  };
  const mc::WrittenTableDigest written = write_and_digest(path, columns, 3 * numbers().size());
  EXPECT_EQ(written.rows, 3 * numbers().size());
  EXPECT_EQ(written.first_rowid, 10);
  EXPECT_EQ(written.last_rowid, 10 + 3 * (static_cast<std::int64_t>(written.rows) - 1));
  ASSERT_EQ(written.digests.size(), columns.size() + 1);
  expect_digests_of_the_file(path, written);
  std::filesystem::remove(path);
}

TEST(ColumnsDigester, AConversionItDoesNotMirrorIsRefused) {
  const std::vector<mc::DeclaredColumn> columns = {
      {"fid", "INTEGER", true}, {"n", "INTEGER", false}, {"r", "REAL", false},
      {"b", "BOOLEAN", false},  {"t", "TEXT", false},
  };
  // Feeds the rows' values, each row ended: true when the digester took them all.
  const auto takes = [&](const std::vector<std::vector<Value>>& rows) {
    mc::ColumnsDigester digester("segments", columns);
    try {
      for (const std::vector<Value>& row : rows) add_row(digester, row);
      return digester.finish().rows == rows.size();
    } catch (const std::logic_error&) {
      return false;
    }
  };
  const Value null = nullptr;
  const Value one = std::int64_t{1};
  EXPECT_TRUE(takes({{one, std::int64_t{-5}, 0.5, one, std::string("7")}}));
  EXPECT_TRUE(takes({{one, 2.0, -0.0, 1.0, null}, {std::int64_t{2}, null, null, null, null}}));
  EXPECT_FALSE(takes({{null, null, null, null, null}})) << "a NULL rowid";
  EXPECT_FALSE(takes({{std::nan(""), null, null, null, null}})) << "a NaN (NULL) rowid";
  EXPECT_FALSE(takes({{Blob{"1"}, null, null, null, null}})) << "a blob rowid";
  EXPECT_FALSE(takes({{one, std::string("7"), null, null, null}})) << "text, INTEGER column";
  EXPECT_FALSE(takes({{one, null, std::string("0.5"), null, null}})) << "text, REAL column";
  EXPECT_FALSE(takes({{one, null, null, std::string("1"), null}})) << "text, NUMERIC column";
  EXPECT_FALSE(takes({{one, null, null, null, one}})) << "an integer, TEXT column";
  EXPECT_FALSE(takes({{one, null, null, null, 1.5}})) << "a real, TEXT column";
  EXPECT_FALSE(takes({{one, null, null, null}})) << "a value too few";
  EXPECT_FALSE(takes({{one, null, null, null, null, null}})) << "a value too many";
  EXPECT_FALSE(takes({{one, null, null, null, null}, {one, null, null, null, null}}))
      << "a rowid not above the previous one";
}

TEST(ColumnsDigester, StampWithWrittenDigestsEqualsTheStampFromTheFile) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "columns_digester_stamp.gpkg").string();
  const std::vector<TestColumn> columns = {
      {"n", "INTEGER", numbers()}, {"r", "REAL", numbers()}, {"t", "TEXT", texts()}};
  const mc::WrittenTableDigest written = write_and_digest(path, columns, 100);
  const std::string from_file = mc::stamp_map_id(path, 2);
  EXPECT_EQ(mc::stamp_map_id(path, 2, written), from_file);
  EXPECT_EQ(mc::stamp_map_id(path, 1, written), from_file);

  // Digests that do not fit the file: refused, and the stored map_id left as it was.
  const auto refused = [&](const std::string& what, auto&& change) {
    mc::WrittenTableDigest other = written;
    change(other);
    EXPECT_THROW(mc::stamp_map_id(path, 2, other), std::logic_error) << what;
  };
  refused("no rows digested", [](mc::WrittenTableDigest& w) { w.rows = 0; });
  refused("another last fid", [](mc::WrittenTableDigest& w) { *w.last_rowid += 1; });
  refused("another first fid", [](mc::WrittenTableDigest& w) { *w.first_rowid -= 1; });
  refused("another declared type",
          [](mc::WrittenTableDigest& w) { w.columns[1].declared_type = "REAL"; });
  refused("a column fewer", [](mc::WrittenTableDigest& w) {
    w.columns.pop_back();
    w.digests.pop_back();
  });
  refused("another table", [](mc::WrittenTableDigest& w) { w.table = "crossings"; });
  {
    sqlite::Database db(path, SQLITE_OPEN_READWRITE);
    db.exec("INSERT INTO segments (fid, n) VALUES (5, 1)");  // a row the digests lack
  }
  EXPECT_THROW(mc::stamp_map_id(path, 2, written), std::logic_error);
  sqlite::Database db(path, SQLITE_OPEN_READONLY);
  auto stored = db.prepare("SELECT value FROM roadcross_metadata WHERE key = 'map_id'");
  ASSERT_TRUE(stored.step());
  EXPECT_EQ(stored.column_text(0), from_file);
  std::filesystem::remove(path);
}

}  // namespace
