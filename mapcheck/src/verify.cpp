#include "roadcross/mapcheck/verify.hpp"

#include <sys/stat.h>

#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <span>

#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross::mapcheck {

namespace {

/// Problems of one kind beyond this many are summed up in one line.
constexpr std::size_t kMaxProblemsPerCheck = 10;
/// An R*Tree box is stored in 32-bit floats rounded outwards: at UTM northings (< 10^7 m) that
/// moves an edge by at most 1 m.
constexpr double kRtreeTolerance_m = 1.0;
/// The sight distance columns a schema version 1 map lacks (the last ones of segment_columns()).
constexpr std::size_t kColumnsAddedInVersion2 = 4;

/// Collects at most kMaxProblemsPerCheck problems of one check, then counts the rest.
class ProblemList {
 public:
  ProblemList(std::vector<std::string>& out, std::string check)
      : out_(out), check_(std::move(check)) {}
  ~ProblemList() {
    if (dropped_ > 0) {
      out_.push_back(check_ + ": and " + std::to_string(dropped_) + " more like the above");
    }
  }
  void add(const std::string& problem) {
    if (count_++ < kMaxProblemsPerCheck) {
      out_.push_back(check_ + ": " + problem);
    } else {
      ++dropped_;
    }
  }

 private:
  std::vector<std::string>& out_;
  std::string check_;
  std::size_t count_ = 0;
  std::size_t dropped_ = 0;
};

void check_integrity(sqlite::Database& db, std::vector<std::string>& problems) {
  ProblemList list(problems, "integrity_check");
  auto check = db.prepare("PRAGMA integrity_check");
  while (check.step()) {
    const std::string line = check.column_text(0);
    if (line != "ok") list.add(line);
  }
}

bool has_table(sqlite::Database& db, std::string_view table) {
  auto query = db.prepare("SELECT count(*) FROM sqlite_master WHERE name = ?1");
  query.bind(1, table);
  query.step();
  return query.column_int64(0) > 0;
}

std::map<std::string, std::string> read_metadata(sqlite::Database& db) {
  std::map<std::string, std::string> metadata;
  auto rows = db.prepare("SELECT key, value FROM " + std::string(schema::kMetadataTable));
  while (rows.step()) metadata[rows.column_text(0)] = rows.column_text(1);
  return metadata;
}

/// The table's columns against the contract: fid, geom, then `expected` (of which the last
/// `optional_tail` may be missing, for older schema versions).
void check_columns(sqlite::Database& db, std::string_view table,
                   const std::vector<schema::Column>& expected, std::size_t optional_tail,
                   std::vector<std::string>& problems) {
  std::vector<std::pair<std::string, std::string>> want = {
      {"fid", "INTEGER"}, {std::string(schema::kGeometryColumn), ""}};
  for (const schema::Column& column : expected) {
    // The declared type is the SQL type's first word (NOT NULL, DEFAULT are constraints).
    const std::string sql_type(column.sql_type);
    want.emplace_back(std::string(column.name), sql_type.substr(0, sql_type.find(' ')));
  }
  auto info = db.prepare("SELECT name, type FROM pragma_table_info(?1) ORDER BY cid");
  info.bind(1, table);
  std::vector<std::pair<std::string, std::string>> have;
  while (info.step()) have.emplace_back(info.column_text(0), info.column_text(1));
  const std::string where = "schema: table " + std::string(table);
  if (have.size() > want.size() || have.size() + optional_tail < want.size()) {
    problems.push_back(where + " has " + std::to_string(have.size()) + " columns, expected " +
                       std::to_string(want.size()));
  }
  for (std::size_t i = 0; i < std::min(have.size(), want.size()); ++i) {
    const bool type_ok = want[i].second.empty() || have[i].second == want[i].second;
    if (have[i].first != want[i].first || !type_ok) {
      problems.push_back(where + " column " + std::to_string(i + 1) + " is " + have[i].first + " " +
                         have[i].second + ", expected " + want[i].first + " " + want[i].second);
    }
  }
}

/// Schema checks; false when the map is too far from a roadcross map to check its content.
bool check_schema(sqlite::Database& db, const std::map<std::string, std::string>& metadata,
                  std::vector<std::string>& problems) {
  auto pragma = db.prepare("PRAGMA application_id");
  if (!pragma.step() || pragma.column_int64(0) != schema::kGpkgApplicationId) {
    problems.push_back("schema: not a GeoPackage (SQLite application_id is not 'GPKG')");
  }
  const auto version = metadata.find(std::string(schema::meta::kSchemaVersion));
  int schema_version = 0;
  if (version == metadata.end()) {
    problems.push_back("schema: roadcross_metadata has no schema_version");
  } else {
    schema_version = std::atoi(version->second.c_str());
    if (schema_version < schema::kOldestReadableVersion ||
        schema_version > schema::kSchemaVersion) {
      problems.push_back("schema: schema_version " + version->second + " is not one this " +
                         "roadcross reads (" + std::to_string(schema::kOldestReadableVersion) +
                         ".." + std::to_string(schema::kSchemaVersion) + ")");
    }
  }
  bool content_checkable = true;
  for (std::string_view table : {schema::kSegmentsTable, schema::kSegmentsRtree,
                                 schema::kCrossingsTable, schema::kCrossingsRtree}) {
    if (!has_table(db, table)) {
      problems.push_back("schema: no table " + std::string(table));
      content_checkable = false;
    }
  }
  if (!content_checkable) return false;
  const std::size_t optional_tail = schema_version < 2 ? kColumnsAddedInVersion2 : 0;
  check_columns(db, schema::kSegmentsTable, schema::segment_columns(), optional_tail, problems);
  check_columns(db, schema::kCrossingsTable, schema::crossing_columns(), 0, problems);
  return true;
}

/// Every row of `table` has an R*Tree box equal (within float rounding) to its geometry's
/// envelope, and every box a row.
void check_rtree(
    sqlite::Database& db, std::string_view table, std::string_view rtree,
    const std::function<std::optional<schema::Envelope>(std::span<const std::uint8_t>)>&
        envelope_of_blob,
    std::vector<std::string>& problems) {
  ProblemList list(problems, "R*Tree " + std::string(rtree));
  const std::string t(table), r(rtree);
  auto rows = db.prepare("SELECT t.fid, t." + std::string(schema::kGeometryColumn) +
                         ", r.id, r.minx, r.maxx, r.miny, r.maxy FROM " + t + " t LEFT JOIN " + r +
                         " r ON r.id = t.fid ORDER BY t.fid");
  while (rows.step()) {
    const std::string row = std::string(table) + " fid " + std::to_string(rows.column_int64(0));
    if (rows.column_is_null(2)) {
      list.add(row + " has no box");
      continue;
    }
    const std::optional<schema::Envelope> envelope = envelope_of_blob(rows.column_blob(1));
    if (!envelope) {
      list.add(row + ": geometry is not a valid GeoPackage geometry of this table");
      continue;
    }
    const double box[4] = {rows.column_double(3), rows.column_double(4), rows.column_double(5),
                           rows.column_double(6)};
    const double want[4] = {envelope->min_x, envelope->max_x, envelope->min_y, envelope->max_y};
    for (int i = 0; i < 4; ++i) {
      if (!(std::fabs(box[i] - want[i]) <= kRtreeTolerance_m)) {
        list.add(row + ": box differs from the geometry's envelope");
        break;
      }
    }
  }
  auto orphans = db.prepare("SELECT id FROM " + r + " WHERE id NOT IN (SELECT fid FROM " + t +
                            ") ORDER BY id");
  while (orphans.step()) {
    list.add("box " + std::to_string(orphans.column_int64(0)) + " has no row in " + t);
  }
}

std::optional<schema::Envelope> linestring_envelope(std::span<const std::uint8_t> blob) {
  std::vector<schema::PlanePoint> points;
  if (!schema::decode_linestring(blob, points) || points.size() < 2) return std::nullopt;
  return schema::envelope_of(points);
}

std::optional<schema::Envelope> point_envelope(std::span<const std::uint8_t> blob) {
  const std::optional<schema::PlanePoint> point = schema::decode_point(blob);
  if (!point) return std::nullopt;
  return schema::Envelope{point->x, point->x, point->y, point->y};
}

void check_content(sqlite::Database& db, const std::map<std::string, std::string>& metadata,
                   VerifyResult& result) {
  const ContentDigest content = compute_content_digest(db.handle());
  result.computed_map_id = content.map_id;
  const std::string prefix(schema::meta::kContentDigestPrefix);
  std::size_t stored_digests = 0;
  for (const auto& [key, value] : metadata) stored_digests += key.starts_with(prefix) ? 1 : 0;
  ProblemList list(result.problems, "content");
  if (result.stored_map_id.empty()) {
    list.add("the map has no map_id (built by a roadcross-build older than 0.2?): rebuild it");
    return;
  }
  std::size_t present = 0;
  for (const ColumnDigest& column : content.columns) {
    const auto stored = metadata.find(column.metadata_key());
    if (stored == metadata.end()) {
      list.add(column.table + "." + column.column + " has no stored digest (a column added?)");
      continue;
    }
    ++present;
    if (stored->second != column.sha256_hex) {
      list.add(column.table + "." + column.column + " differs from the content the build hashed");
    }
  }
  if (stored_digests > present) {
    list.add(std::to_string(stored_digests - present) +
             " stored column digests name no column of the map (a column or table removed?)");
  }
  if (content.map_id != result.stored_map_id) {
    list.add("map_id " + result.stored_map_id + " does not match the content (" + content.map_id +
             ")");
  }
}

}  // namespace

VerifyResult verify_map(const std::string& path, const std::string& expected_id) {
  VerifyResult result;
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0 || !S_ISREG(status.st_mode)) {
    result.problems.push_back(path + ": not a regular file");
    return result;
  }
  try {
    sqlite::Database db(path, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX);
    check_integrity(db, result.problems);
    if (!has_table(db, schema::kMetadataTable)) {
      result.problems.push_back("schema: no table " + std::string(schema::kMetadataTable) +
                                ": not a roadcross map");
      return result;
    }
    const std::map<std::string, std::string> metadata = read_metadata(db);
    if (const auto id = metadata.find(std::string(schema::meta::kMapId)); id != metadata.end()) {
      result.stored_map_id = id->second;
    }
    if (!check_schema(db, metadata, result.problems)) return result;
    auto count = db.prepare("SELECT count(*) FROM " + std::string(schema::kSegmentsTable));
    count.step();
    result.segment_count = count.column_int64(0);
    check_rtree(db, schema::kSegmentsTable, schema::kSegmentsRtree, linestring_envelope,
                result.problems);
    check_rtree(db, schema::kCrossingsTable, schema::kCrossingsRtree, point_envelope,
                result.problems);
    check_content(db, metadata, result);
  } catch (const std::exception& e) {
    result.problems.push_back(std::string("cannot read: ") + e.what());
  }
  if (!expected_id.empty() && result.stored_map_id != expected_id) {
    result.problems.push_back("map_id is " +
                              (result.stored_map_id.empty() ? "absent" : result.stored_map_id) +
                              ", expected " + expected_id);
  }
  return result;
}

}  // namespace roadcross::mapcheck
