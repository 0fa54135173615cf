#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "map_impl.hpp"
#include "polyline.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross {

bool disable_sqlite_memory_statistics() noexcept {
  // SQLITE_MISUSE once SQLite is initialised: the setting only exists before that.
  return sqlite3_config(SQLITE_CONFIG_MEMSTATUS, 0) == SQLITE_OK;
}

const char* to_string(StatusCode code) noexcept {
  switch (code) {
    case StatusCode::ok:
      return "ok";
    case StatusCode::file_not_found:
      return "file_not_found";
    case StatusCode::not_a_database:
      return "not_a_database";
    case StatusCode::wrong_version:
      return "wrong_version";
    case StatusCode::corrupt_database:
      return "corrupt_database";
    case StatusCode::invalid_argument:
      return "invalid_argument";
    case StatusCode::not_found:
      return "not_found";
    case StatusCode::internal:
      return "internal";
    case StatusCode::corrupt_segment:
      return "corrupt_segment";
  }
  return "unknown";
}

namespace {

constexpr const char* kRebuildHint =
    "Rebuild it with this version's roadcross-build (roadcross-build --osm MAP.osm.pbf -o "
    "OUT.gpkg).";

/// Address space for reading the DB through a memory map (SQLite caps it at its compile-time
/// SQLITE_MAX_MMAP_SIZE, 2 GB by default); pages beyond it are read with pread().
constexpr std::int64_t kMmapBytes = std::int64_t{1} << 30;

template <typename T>
Result<T> fail(StatusCode code, std::string message) {
  return Result<T>{Status{code, std::move(message)}, std::nullopt};
}

/// The longest string or blob a map may make SQLite read (SQLITE_LIMIT_LENGTH): a roadcross
/// map's longest values are metadata notes and paths, far below this; a hostile map's 1 GB
/// "name" is refused instead of copied into every answer.
constexpr int kMaxValueBytes = 16 << 20;

/// SQLite's progress handler: interrupts the statement when the call's budget is spent.
int spend_work(void* budget) noexcept {
  auto* b = static_cast<detail::WorkBudget*>(budget);
  if (b->ticks_left == 0) return 1;
  --b->ticks_left;
  return 0;
}

/// A file URI for sqlite3_open_v2 with SQLITE_OPEN_URI: every byte outside RFC 3986's
/// unreserved set and '/' percent-encoded, so that no '?', '#' or '%' in a path is read as URI
/// syntax.
std::string file_uri(const std::string& path, std::string_view query) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string uri = "file:";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      uri += static_cast<char>(c);
    } else {
      uri += '%';
      uri += kHex[c >> 4];
      uri += kHex[c & 15];
    }
  }
  return uri + "?" + std::string(query);
}

/// How the file's journal is set up, from its SQLite header (bytes 18 and 19: 1 = rollback
/// journal, 2 = WAL). A file too short to have a header reads as rollback; SQLite then says
/// what is wrong with it.
bool header_says_wal(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file) return false;
  unsigned char header[20] = {};
  const std::size_t got = std::fread(header, 1, sizeof header, file);
  std::fclose(file);
  return got == sizeof header && (header[18] == 2 || header[19] == 2);
}

/// Opens the map read-only. A map in WAL journal mode (left so by a tool that opened it for
/// writing) cannot be read-only opened with the runtime's exclusive locking; with no pending
/// WAL content everything is in the main file, which is then opened as immutable. Pending WAL
/// content (a "-wal" file that is not empty) is an error saying how to merge it.
sqlite::Database open_read_only(const std::string& path, Status& status) {
  constexpr int kFlags = SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX;
  if (!header_says_wal(path)) return sqlite::Database(path, kFlags);
  struct stat wal_status {};
  const std::string wal = path + "-wal";
  if (::stat(wal.c_str(), &wal_status) == 0 && wal_status.st_size > 0) {
    status = {StatusCode::not_a_database,
              path + ": the map is in WAL journal mode with changes not yet merged into it (" +
                  wal + ", " + std::to_string(wal_status.st_size) +
                  " bytes): merge them with sqlite3 " + path +
                  " 'PRAGMA journal_mode = DELETE', or rebuild the map. " + kRebuildHint};
  }
  return sqlite::Database(file_uri(path, "immutable=1"), kFlags | SQLITE_OPEN_URI);
}

/// The connection settings for a file from anywhere: SQLite's defensive mode (no writes to
/// the schema or to shadow tables even by a bug), an untrusted schema (no application
/// functions in views, triggers or indexes), no views and no triggers at all (a roadcross map
/// has no views, and its triggers only maintain the R*Tree on writes, which the runtime never
/// makes), values up to kMaxValueBytes, and the work budget.
void harden(sqlite::Database& db, detail::WorkBudget& budget) {
  sqlite3* handle = db.handle();
  for (const auto& [option, value] :
       {std::pair{SQLITE_DBCONFIG_DEFENSIVE, 1}, std::pair{SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0},
        std::pair{SQLITE_DBCONFIG_ENABLE_VIEW, 0}, std::pair{SQLITE_DBCONFIG_ENABLE_TRIGGER, 0}}) {
    int now = -1;
    if (sqlite3_db_config(handle, option, value, &now) != SQLITE_OK || now != value) {
      throw sqlite::sqlite_error(SQLITE_ERROR, "cannot configure SQLite defensively");
    }
  }
  sqlite3_limit(handle, SQLITE_LIMIT_LENGTH, kMaxValueBytes);
  sqlite3_progress_handler(handle, detail::WorkBudget::kStepsPerTick, spend_work, &budget);
}

bool ends_with(std::string_view text, std::string_view tail) {
  return text.size() >= tail.size() && text.substr(text.size() - tail.size()) == tail;
}

/// A trigger a GeoPackage may carry: the R*Tree triggers (spec F.3), the tile pyramid ones,
/// the core spec's own (gpkg_*) and GDAL's feature-count triggers. They never run here (triggers
/// are off and the connection is read-only); any other trigger means the file was altered.
bool known_trigger(std::string_view name) {
  if (name.starts_with("gpkg_") || name.starts_with("trigger_insert_feature_count_") ||
      name.starts_with("trigger_delete_feature_count_")) {
    return true;
  }
  // The tile pyramid triggers of a tiles table (GeoPackage 1.3, annex F.5), such as the
  // build's terrain tiles.
  for (std::string_view tail : {"_zoom_insert", "_zoom_update", "_tile_column_insert",
                                "_tile_column_update", "_tile_row_insert", "_tile_row_update"}) {
    if (ends_with(name, tail)) return true;
  }
  if (!name.starts_with("rtree_")) return false;
  for (std::string_view tail :
       {"_insert", "_update1", "_update2", "_update3", "_update4", "_delete"}) {
    if (ends_with(name, tail)) return true;
  }
  return false;
}

/// Rejects schema objects that are neither the GeoPackage's nor roadcross's: views, unknown
/// triggers, virtual tables other than R*Trees, and a segments, metadata or R*Tree table of the
/// wrong kind (a `segments` view could run for ever). Ordinary extra tables and indexes are
/// inert data the runtime never reads, and tools that touch a GeoPackage add some (GDAL's
/// gpkg_ogr_contents), so they are allowed.
Status check_schema_objects(sqlite::Database& db, const std::string& path) {
  auto rows = db.prepare("SELECT type, name, coalesce(sql, '') FROM sqlite_master");
  bool segments_ok = false, rtree_ok = false;
  while (rows.step()) {
    const std::string type = rows.column_text(0), name = rows.column_text(1);
    std::string sql = rows.column_text(2);
    for (char& c : sql) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool is_virtual = sql.starts_with("create virtual table");
    const bool is_rtree = is_virtual && sql.find("using rtree(") != std::string::npos;
    std::string problem;
    if (type == "view") {
      problem = "a view '" + name + "' (a roadcross map has none)";
    } else if (type == "trigger" && !known_trigger(name)) {
      problem = "a trigger '" + name + "' that is not one of the GeoPackage's";
    } else if (type == "table" && is_virtual && !(is_rtree && name.starts_with("rtree_"))) {
      problem = "a virtual table '" + name + "' that is not a GeoPackage R*Tree";
    } else if (type == "table" && name == schema::kSegmentsTable) {
      segments_ok = !is_virtual;
    } else if (type == "table" && name == schema::kSegmentsRtree) {
      rtree_ok = is_rtree;
    }
    if (!problem.empty()) {
      return {StatusCode::corrupt_database,
              path + ": the map holds " + problem +
                  ", so it was altered after roadcross-build wrote it and is not read. " +
                  kRebuildHint};
    }
  }
  if (!segments_ok || !rtree_ok) {
    return {StatusCode::corrupt_database,
            path + ": the map lacks an ordinary '" + std::string(schema::kSegmentsTable) +
                "' table with its R*Tree '" + std::string(schema::kSegmentsRtree) + "'. " +
                kRebuildHint};
  }
  return {};
}

bool parse_int(const std::string& text, int& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size();
}

}  // namespace

Map::Map(std::unique_ptr<Impl> impl) noexcept : impl_(std::move(impl)) {}
Map::Map(Map&&) noexcept = default;
Map& Map::operator=(Map&&) noexcept = default;
Map::~Map() = default;

const MapInfo& Map::info() const noexcept {
  return impl_->info;
}

namespace {

bool parse_double(const std::string& text, double& out) {
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
  return ec == std::errc() && end == text.data() + text.size() && std::isfinite(out);
}

/// The map's coverage (MapInfo's extent and coverage_wgs84): from the coverage.* metadata when
/// all eight keys parse, else from gpkg_contents' extent of segments, else (an extent left
/// NULL) from the R*Tree, with the WGS84 box computed from the grid extent.
template <typename ValueOf>
void read_coverage(sqlite::Database& db, ValueOf&& value_of, MapInfo& info) {
  const std::string_view keys[8] = {
      schema::meta::kCoverageMinEasting, schema::meta::kCoverageMinNorthing,
      schema::meta::kCoverageMaxEasting, schema::meta::kCoverageMaxNorthing,
      schema::meta::kCoverageMinLat,     schema::meta::kCoverageMinLon,
      schema::meta::kCoverageMaxLat,     schema::meta::kCoverageMaxLon};
  double values[8] = {};
  bool stored = true;
  for (int i = 0; i < 8 && stored; ++i) {
    const std::string* text = value_of(keys[i]);
    stored = text && parse_double(*text, values[i]);
  }
  if (stored) {
    info.min_easting_m = values[0];
    info.min_northing_m = values[1];
    info.max_easting_m = values[2];
    info.max_northing_m = values[3];
    info.coverage_wgs84 = {values[4], values[5], values[6], values[7]};
    info.coverage_stored = true;
    return;
  }
  auto extent =
      db.prepare("SELECT min_x, min_y, max_x, max_y FROM gpkg_contents WHERE table_name = ?1");
  extent.bind(1, schema::kSegmentsTable);
  const bool has_extent = extent.step() && !extent.column_is_null(0);
  sqlite::Statement* source = &extent;
  std::optional<sqlite::Statement> rtree;
  if (!has_extent) {
    rtree.emplace(db.prepare("SELECT min(minx), min(miny), max(maxx), max(maxy) FROM " +
                             std::string(schema::kSegmentsRtree)));
    if (!rtree->step() || rtree->column_is_null(0)) return;  // no segment at all
    source = &*rtree;
  }
  info.min_easting_m = source->column_double(0);
  info.min_northing_m = source->column_double(1);
  info.max_easting_m = source->column_double(2);
  info.max_northing_m = source->column_double(3);
  info.coverage_wgs84 = geo::wgs84_box_of_utm_rectangle(
      info.zone, info.min_easting_m, info.min_northing_m, info.max_easting_m, info.max_northing_m);
}

Status read_metadata(sqlite::Database& db, MapInfo& info) {
  const std::string& path = info.path;
  std::int64_t application_id = 0;
  {
    auto pragma = db.prepare("PRAGMA application_id");
    if (pragma.step()) application_id = pragma.column_int64(0);
  }
  if (application_id != schema::kGpkgApplicationId) {
    return {StatusCode::not_a_database, path + ": not a GeoPackage (SQLite application_id is " +
                                            std::to_string(application_id) +
                                            ", expected 'GPKG'). " + kRebuildHint};
  }
  {
    auto has_table =
        db.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?1");
    has_table.bind(1, schema::kMetadataTable);
    has_table.step();
    if (has_table.column_int64(0) == 0) {
      return {StatusCode::not_a_database,
              path + ": a GeoPackage, but not written by roadcross-build (no table " +
                  std::string(schema::kMetadataTable) + "). " + kRebuildHint};
    }
  }
  const Status objects = check_schema_objects(db, path);
  if (!objects.ok()) return objects;
  auto rows =
      db.prepare("SELECT key, value FROM " + std::string(schema::kMetadataTable) + " ORDER BY key");
  while (rows.step()) {
    info.metadata.emplace_back(detail::valid_utf8(rows.column_text_view(0)),
                               detail::valid_utf8(rows.column_text_view(1)));
  }

  auto value_of = [&](std::string_view key) -> const std::string* {
    for (const auto& [k, v] : info.metadata) {
      if (k == key) return &v;
    }
    return nullptr;
  };
  const std::string* version = value_of(schema::meta::kSchemaVersion);
  if (!version || !parse_int(*version, info.schema_version)) {
    return {StatusCode::corrupt_database,
            path + ": roadcross metadata has no valid schema_version. " + kRebuildHint};
  }
  if (info.schema_version > schema::kSchemaVersion) {
    return {
        StatusCode::wrong_version,
        path + ": written with roadcross schema version " + *version +
            ", newer than this runtime reads (" + std::to_string(schema::kOldestReadableVersion) +
            ".." + std::to_string(schema::kSchemaVersion) +
            "). Update the runtime, or rebuild the DB with the roadcross-build that matches it."};
  }
  if (info.schema_version < schema::kOldestReadableVersion) {
    return {StatusCode::wrong_version, path + ": written with roadcross schema version " +
                                           *version + ", older than this runtime reads (" +
                                           std::to_string(schema::kOldestReadableVersion) + ".." +
                                           std::to_string(schema::kSchemaVersion) + "). " +
                                           kRebuildHint};
  }
  const std::string* zone = value_of(schema::meta::kUtmZone);
  const std::string* northern = value_of(schema::meta::kUtmNorthern);
  const std::string* epsg = value_of(schema::meta::kEpsg);
  int northern_flag = 0;
  if (!zone || !northern || !epsg || !parse_int(*zone, info.zone.zone) ||
      !parse_int(*northern, northern_flag) || !parse_int(*epsg, info.epsg) || info.zone.zone < 1 ||
      info.zone.zone > 60) {
    return {StatusCode::corrupt_database,
            path + ": roadcross metadata lacks a valid UTM zone. " + kRebuildHint};
  }
  info.zone.northern = northern_flag != 0;
  if (const std::string* tool = value_of(schema::meta::kToolVersion)) info.tool_version = *tool;
  if (const std::string* id = value_of(schema::meta::kMapId)) info.map_id = *id;
  if (const std::string* time = value_of(schema::meta::kOsmTimestamp)) info.osm_timestamp = *time;
  if (const std::string* count = value_of(schema::meta::kSegmentCount)) {
    info.segment_count = std::strtoll(count->c_str(), nullptr, 10);
  }
  read_coverage(db, value_of, info);
  return {};
}

}  // namespace

Result<Map> Map::open(const std::string& path) noexcept {
  try {
    struct stat file_status {};
    if (::stat(path.c_str(), &file_status) != 0 || !S_ISREG(file_status.st_mode)) {
      return fail<Map>(
          StatusCode::file_not_found,
          path + ": no such file. Build one with roadcross-build --osm MAP -o " + path);
    }
    Status status;
    sqlite::Database db = open_read_only(path, status);
    if (!status.ok()) return Result<Map>{std::move(status), std::nullopt};
    auto budget = std::make_unique<detail::WorkBudget>();
    harden(db, *budget);
    // Hot-path settings (docs/runtime.md, "The DB file while a Map is open"): keep the shared
    // lock from the first read on, so a statement neither takes and drops a file lock nor checks
    // for a hot journal and a changed file (three system calls per statement otherwise), and
    // read pages through a memory map instead of one pread() each.
    db.exec("PRAGMA locking_mode = EXCLUSIVE");
    db.exec("PRAGMA mmap_size = " + std::to_string(kMmapBytes));
    MapInfo info;
    info.path = path;
    status = read_metadata(db, info);
    detail::Thresholds thresholds;
    if (status.ok()) status = detail::thresholds_from(info, thresholds);
    if (!status.ok()) return Result<Map>{std::move(status), std::nullopt};
    auto impl =
        std::make_unique<Impl>(std::move(budget), std::move(db), std::move(info), thresholds);
    return Result<Map>{Status{}, Map(std::move(impl))};
  } catch (const sqlite::sqlite_error& e) {
    if ((e.code() & 0xff) == SQLITE_NOTADB) {
      return fail<Map>(StatusCode::not_a_database,
                       path + ": not an SQLite database, so not a roadcross map. " + kRebuildHint);
    }
    if ((e.code() & 0xff) == SQLITE_CANTOPEN) {
      return fail<Map>(StatusCode::file_not_found, path + ": cannot open: " + e.what());
    }
    if ((e.code() & 0xff) == SQLITE_INTERRUPT || (e.code() & 0xff) == SQLITE_TOOBIG) {
      return Result<Map>{detail::status_of(e, path), std::nullopt};
    }
    return fail<Map>(StatusCode::not_a_database, path + ": " + e.what());
  } catch (const std::exception& e) {
    return fail<Map>(StatusCode::internal, path + ": " + e.what());
  }
}

Status Map::Impl::to_plane(const Position& position, schema::PlanePoint& out) const noexcept {
  if (!std::isfinite(position.first) || !std::isfinite(position.second)) {
    return {StatusCode::invalid_argument, "position has a NaN or infinite coordinate"};
  }
  const bool own_zone = position.zone.zone == 0 || position.zone == info.zone;
  if (position.kind == Position::Kind::utm && own_zone) {
    out = {position.first, position.second};
    return {};
  }
  try {
    geo::LatLon ll{position.first, position.second};
    if (position.kind == Position::Kind::utm) {
      if (position.zone.zone < 1 || position.zone.zone > 60) {
        return {StatusCode::invalid_argument,
                "UTM zone " + std::to_string(position.zone.zone) + " is not in 1..60"};
      }
      ll = geo::utm_to_wgs84(position.first, position.second, position.zone);
    }
    const geo::UtmPoint p = geo::wgs84_to_utm(ll.lat_deg, ll.lon_deg, info.zone);
    out = {p.easting_m, p.northing_m};
    return {};
  } catch (const std::exception& e) {
    return {StatusCode::invalid_argument, e.what()};
  }
}

Result<PlanePoint> Map::to_utm(const Position& position) const noexcept {
  schema::PlanePoint p;
  Status status = impl_->to_plane(position, p);
  if (!status.ok()) return Result<PlanePoint>{std::move(status), std::nullopt};
  return Result<PlanePoint>{Status{}, PlanePoint{p.x, p.y}};
}

Status Map::Impl::locate(const Position& position, double max_distance_m, NearestRoad& road,
                         double region_reach_m) {
  schema::PlanePoint p;
  Status status = to_plane(position, p);
  if (!status.ok()) return status;
  std::int64_t best_id = -1;
  std::size_t best_row = 0;
  detail::PolylineProjection best;
  best.distance_m = std::numeric_limits<double>::infinity();
  located_rows = 0;
  // Grow the search box until the best candidate is inside the searched radius: then no
  // segment outside the box can be nearer, since its bounding box would intersect it.
  constexpr double kFirstRadiusM = 16.0;
  for (double radius_m = std::min(kFirstRadiusM + region_reach_m, max_distance_m);;
       radius_m = std::min(radius_m * 2.0, max_distance_m)) {
    sqlite::Statement& stmt = queries.candidates;
    stmt.bind(1, p.x - radius_m);
    stmt.bind(2, p.x + radius_m);
    stmt.bind(3, p.y - radius_m);
    stmt.bind(4, p.y + radius_m);
    std::size_t count = 0;
    while (stmt.step()) {
      if (count == region_segments.size()) region_segments.emplace_back();
      detail::RegionSegment& row = region_segments[count];
      row.id = stmt.column_int64(0);
      if (!schema::decode_linestring(stmt.column_blob(1), row.points)) {
        stmt.reset();
        throw detail::corrupt_segment_error(detail::segment_problem(row.id, "malformed geometry"));
      }
      try {
        detail::check_in_box(row.id, row.points, stmt.column_double(2), stmt.column_double(3),
                             stmt.column_double(4), stmt.column_double(5));
      } catch (...) {
        stmt.reset();
        throw;
      }
      const auto projection = detail::project_onto_polyline(row.points, p);
      if (projection.distance_m < best.distance_m) {
        best_id = row.id;
        best = projection;
      }
      if (row.id == best_id) best_row = count;  // a larger box reads the best again
      ++count;
    }
    stmt.reset();
    located_rows = count;
    located_at = p;
    located_half_m = radius_m;
    if (best.distance_m <= radius_m || radius_m >= max_distance_m) break;
  }
  if (best_id < 0 || best.distance_m > max_distance_m) {
    char text[160];
    std::snprintf(text, sizeof text, "no road within %g m of E %.1f N %.1f (UTM zone %d%s)",
                  max_distance_m, p.x, p.y, info.zone.zone, info.zone.northern ? "N" : "S");
    return {StatusCode::not_found, text};
  }
  best_geometry = region_segments[best_row].points;
  road.segment_id = best_id;
  road.query = {p.x, p.y};
  road.closest = {best.closest.x, best.closest.y};
  road.distance_m = best.distance_m;
  return {};
}

Result<NearestRoad> Map::nearest(const Position& position, double max_distance_m) noexcept {
  if (!(max_distance_m > 0.0 && max_distance_m <= detail::kMaxSearchDistanceM)) {
    return fail<NearestRoad>(StatusCode::invalid_argument,
                             "max_distance_m must be in (0, 100000] metres");
  }
  impl_->budget->restart();
  try {
    Impl& impl = *impl_;
    NearestRoad road;
    Status status = impl.locate(position, max_distance_m, road);
    if (!status.ok()) return Result<NearestRoad>{std::move(status), std::nullopt};
    sqlite::Statement& attributes = impl.queries.attributes;
    attributes.bind(1, road.segment_id);
    if (attributes.step()) {
      using C = schema::SegmentColumn;
      const schema::SegmentSelection& at = detail::kIdentityColumns;
      road.osm_way_id = attributes.column_int64(at[C::osm_way_id]);
      road.highway = detail::valid_utf8(attributes.column_text_view(at[C::highway]));
      road.name = detail::valid_utf8(attributes.column_text_view(at[C::name]));
      road.segment_length_m = attributes.column_double(at[C::length_m]);
    }
    attributes.reset();
    if (!(road.segment_length_m >= 0.0 && std::isfinite(road.segment_length_m))) {
      throw detail::corrupt_segment_error(
          detail::segment_problem(road.segment_id, "length_m must be a finite number >= 0"));
    }
    return Result<NearestRoad>{Status{}, std::move(road)};
  } catch (const std::exception& e) {
    impl_->queries.candidates.reset();
    impl_->queries.attributes.reset();
    return Result<NearestRoad>{detail::status_of(e, impl_->info.path), std::nullopt};
  }
}

int Map::Impl::side_of(const NearestRoad& road) const noexcept {
  constexpr double kOnCentrelineM = 1e-3;
  if (road.distance_m < kOnCentrelineM || best_geometry.size() < 2) return 0;
  const schema::PlanePoint query{road.query.easting_m, road.query.northing_m};
  const detail::PolylineProjection at = detail::project_onto_polyline(best_geometry, query);
  const double yaw = detail::polyline_direction_rad(best_geometry, at);
  // The cross product of the road direction with the offset to the query: > 0 on the left.
  const double cross =
      std::cos(yaw) * (query.y - at.closest.y) - std::sin(yaw) * (query.x - at.closest.x);
  return cross >= 0.0 ? 1 : -1;
}

double Map::Impl::direction_at(std::int64_t segment_id, const detail::PolylineProjection& at) {
  const std::vector<schema::PlanePoint>& own = best_geometry;
  const double own_direction = detail::polyline_direction_rad(own, at);
  const bool at_start = at.edge_index == 0 && at.edge_fraction <= 0.0;
  const bool at_end = at.edge_index + 2 == own.size() && at.edge_fraction >= 1.0;
  if (!at_start && !at_end) return own_direction;

  // Every segment whose box holds the vertex; those that share its graph node continue the
  // road there (a bridge over it shares the point, not the node).
  struct Other {
    std::int64_t from = 0, to = 0;
    double leaving_from = 0.0, leaving_to = 0.0;  // direction away from each end, along it
  };
  std::vector<Other> others;
  std::int64_t own_from = 0, own_to = 0;
  const schema::PlanePoint vertex = at_start ? own.front() : own.back();
  constexpr double kHalfBoxM = 0.01;
  sqlite::Statement& stmt = queries.segments_at;
  stmt.bind(1, vertex.x - kHalfBoxM);
  stmt.bind(2, vertex.x + kHalfBoxM);
  stmt.bind(3, vertex.y - kHalfBoxM);
  stmt.bind(4, vertex.y + kHalfBoxM);
  using C = schema::SegmentColumn;
  const int from_column = detail::kEndNodeColumns[C::from_node_id];
  const int to_column = detail::kEndNodeColumns[C::to_node_id];
  while (stmt.step()) {
    const std::int64_t fid = stmt.column_int64(0);
    if (fid == segment_id) {
      own_from = stmt.column_int64(from_column);
      own_to = stmt.column_int64(to_column);
      continue;
    }
    if (!schema::decode_linestring(stmt.column_blob(1), scratch)) {
      stmt.reset();
      throw detail::corrupt_segment_error(detail::segment_problem(fid, "malformed geometry"));
    }
    try {
      detail::check_in_box(fid, scratch, stmt.column_double(4), stmt.column_double(5),
                           stmt.column_double(6), stmt.column_double(7));
    } catch (...) {
      stmt.reset();
      throw;
    }
    const std::size_t n = scratch.size();
    others.push_back({stmt.column_int64(from_column), stmt.column_int64(to_column),
                      geo::grid_yaw_rad(scratch[1].x - scratch[0].x, scratch[1].y - scratch[0].y),
                      geo::grid_yaw_rad(scratch[n - 2].x - scratch[n - 1].x,
                                        scratch[n - 2].y - scratch[n - 1].y)});
  }
  stmt.reset();
  if (own_from == own_to) return own_direction;  // a loop: both ends are the same node
  const std::int64_t node = at_start ? own_from : own_to;
  int ends_at_node = 0;
  double leaving = 0.0;  // direction away from the node along the one other segment
  for (const Other& o : others) {
    if (o.from == node) {
      ++ends_at_node;
      leaving = o.leaving_from;
    }
    if (o.to == node) {
      ++ends_at_node;
      leaving = o.leaving_to;
    }
  }
  if (ends_at_node != 1) return own_direction;  // a dead end or a junction
  // The road arrives at the node by `before` and leaves it by `after`, in the own segment's
  // direction of travel.
  const double before = at_end ? own_direction : geo::normalize_angle_rad(leaving + geo::kPi);
  const double after = at_end ? leaving : own_direction;
  return geo::normalize_angle_rad(before + 0.5 * geo::angle_difference_rad(after, before));
}

Result<RoadHeading> Map::road_heading(const Position& position, double max_distance_m) noexcept {
  Result<NearestRoad> road = nearest(position, max_distance_m);
  if (!road.ok()) return fail<RoadHeading>(road.status.code, road.status.message);
  const std::vector<schema::PlanePoint>& geometry = impl_->best_geometry;
  const schema::PlanePoint query{road->query.easting_m, road->query.northing_m};
  const detail::PolylineProjection at = detail::project_onto_polyline(geometry, query);

  RoadHeading heading;
  try {
    heading.road_heading_rad = impl_->direction_at(road->segment_id, at);
  } catch (const std::exception& e) {
    impl_->queries.segments_at.reset();
    return Result<RoadHeading>{detail::status_of(e, impl_->info.path), std::nullopt};
  }
  // Which side of the road is the query on? The sign of the cross product of the road
  // direction with the vector from the road to the query: > 0 means left of the way direction.
  const double dir_x = std::cos(heading.road_heading_rad),
               dir_y = std::sin(heading.road_heading_rad);
  const double off_x = query.x - at.closest.x, off_y = query.y - at.closest.y;
  const double side = dir_x * off_y - dir_y * off_x;
  constexpr double kOnCentrelineM = 1e-3;
  heading.on_centreline = road->distance_m < kOnCentrelineM;
  // Left of the road -> cross towards the right (yaw - pi/2), and vice versa.
  const double normal = (side >= 0.0 || heading.on_centreline) ? -geo::kPi / 2.0 : geo::kPi / 2.0;
  heading.crossing_heading_rad = geo::normalize_angle_rad(heading.road_heading_rad + normal);
  heading.road_bearing_deg = geo::yaw_rad_to_bearing_deg(heading.road_heading_rad);
  heading.crossing_bearing_deg = geo::yaw_rad_to_bearing_deg(heading.crossing_heading_rad);
  try {
    const geo::LatLon ll = geo::utm_to_wgs84(query.x, query.y, impl_->info.zone);
    heading.convergence_rad =
        geo::wgs84_to_utm(ll.lat_deg, ll.lon_deg, impl_->info.zone).convergence_rad;
  } catch (const std::exception&) {
    heading.convergence_rad = 0.0;  // only outside the UTM domain, which nearest() rejected
  }
  if (position.uncertainty) {
    detail::RegionGeometry region;
    try {
      Status status = impl_->region_geometry(*position.uncertainty, *road, region);
      if (!status.ok()) return fail<RoadHeading>(status.code, status.message);
    } catch (const std::exception& e) {
      impl_->queries.candidates.reset();
      return fail<RoadHeading>(StatusCode::corrupt_database, impl_->info.path + ": " + e.what());
    }
    heading.heading_spread_rad = region.heading_spread_rad;
  }
  heading.road = std::move(*road);
  return Result<RoadHeading>{Status{}, std::move(heading)};
}

namespace detail {

namespace {
/// The length of the valid UTF-8 sequence at the start of `s` (1..4), or 0 when it is not one
/// (RFC 3629: no overlong forms, no surrogates, nothing above U+10FFFF).
std::size_t utf8_sequence_length(std::string_view s) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const unsigned char lead = byte(0);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned char low = 0x80, high = 0xBF;  // range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;
    if (lead == 0xED) high = 0x9F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;
    if (lead == 0xF4) high = 0x8F;
  } else {
    return 0;
  }
  if (s.size() < length || byte(1) < low || byte(1) > high) return 0;
  for (std::size_t i = 2; i < length; ++i) {
    if (byte(i) < 0x80 || byte(i) > 0xBF) return 0;
  }
  return length;
}
}  // namespace

std::string valid_utf8(std::string_view text) {
  const bool ascii = std::all_of(text.begin(), text.end(),
                                 [](char c) { return static_cast<unsigned char>(c) < 0x80; });
  if (ascii) return std::string(text);
  std::string out;
  out.reserve(text.size() + 8);
  while (!text.empty()) {
    const std::size_t length = utf8_sequence_length(text);
    if (length == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
      text.remove_prefix(1);
    } else {
      out.append(text.substr(0, length));
      text.remove_prefix(length);
    }
  }
  return out;
}

std::string segment_problem(std::int64_t fid, const std::string& what) {
  return "segment " + std::to_string(fid) + ": " + what;
}

void check_in_box(std::int64_t fid, const std::vector<schema::PlanePoint>& points, double min_x,
                  double max_x, double min_y, double max_y) {
  for (const schema::PlanePoint& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      throw corrupt_segment_error(segment_problem(fid, "a geometry coordinate is not finite"));
    }
    // Negated so that a NaN box edge fails too.
    if (!(p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y)) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "its R*Tree box (E %.1f..%.1f, N %.1f..%.1f) does not contain its point "
                    "E %.1f N %.1f",
                    min_x, max_x, min_y, max_y, p.x, p.y);
      throw corrupt_segment_error(segment_problem(fid, text));
    }
  }
}

Status status_of(const std::exception& error, const std::string& path) {
  if (dynamic_cast<const corrupt_segment_error*>(&error)) {
    return {StatusCode::corrupt_segment,
            path + ": " + error.what() + ". The map is damaged there. " + kRebuildHint};
  }
  if (const auto* sql = dynamic_cast<const sqlite::sqlite_error*>(&error)) {
    if ((sql->code() & 0xff) == SQLITE_INTERRUPT) {
      return {StatusCode::corrupt_database,
              path + ": a query made SQLite do more than " +
                  std::to_string(WorkBudget::kTicksPerCall * WorkBudget::kStepsPerTick) +
                  " steps of work and was stopped: the map is damaged or hostile. " + kRebuildHint};
    }
    if ((sql->code() & 0xff) == SQLITE_TOOBIG) {
      return {StatusCode::corrupt_database,
              path + ": a value in the map is longer than " + std::to_string(kMaxValueBytes) +
                  " bytes, which no roadcross map holds. " + kRebuildHint};
    }
  }
  return {StatusCode::corrupt_database, path + ": " + error.what()};
}

}  // namespace detail

}  // namespace roadcross
