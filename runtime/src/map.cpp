#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
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
  auto rows =
      db.prepare("SELECT key, value FROM " + std::string(schema::kMetadataTable) + " ORDER BY key");
  while (rows.step()) info.metadata.emplace_back(rows.column_text(0), rows.column_text(1));

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
  if (const std::string* count = value_of(schema::meta::kSegmentCount)) {
    info.segment_count = std::strtoll(count->c_str(), nullptr, 10);
  }
  auto extent =
      db.prepare("SELECT min_x, min_y, max_x, max_y FROM gpkg_contents WHERE table_name = ?1");
  extent.bind(1, schema::kSegmentsTable);
  if (extent.step()) {
    info.min_easting_m = extent.column_double(0);
    info.min_northing_m = extent.column_double(1);
    info.max_easting_m = extent.column_double(2);
    info.max_northing_m = extent.column_double(3);
  }
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
    sqlite::Database db(path, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX);
    // Hot-path settings (docs/runtime.md, "The DB file while a Map is open"): keep the shared
    // lock from the first read on, so a statement neither takes and drops a file lock nor checks
    // for a hot journal and a changed file (three system calls per statement otherwise), and
    // read pages through a memory map instead of one pread() each.
    db.exec("PRAGMA locking_mode = EXCLUSIVE");
    db.exec("PRAGMA mmap_size = " + std::to_string(kMmapBytes));
    MapInfo info;
    info.path = path;
    Status status = read_metadata(db, info);
    if (!status.ok()) return Result<Map>{std::move(status), std::nullopt};
    auto impl = std::make_unique<Impl>(std::move(db), std::move(info));
    return Result<Map>{Status{}, Map(std::move(impl))};
  } catch (const sqlite::sqlite_error& e) {
    if ((e.code() & 0xff) == SQLITE_NOTADB) {
      return fail<Map>(StatusCode::not_a_database,
                       path + ": not an SQLite database, so not a roadcross map. " + kRebuildHint);
    }
    if ((e.code() & 0xff) == SQLITE_CANTOPEN) {
      return fail<Map>(StatusCode::file_not_found, path + ": cannot open: " + e.what());
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
  if (position.kind == Position::Kind::utm) {
    out = {position.first, position.second};
    return {};
  }
  try {
    const geo::UtmPoint p = geo::wgs84_to_utm(position.first, position.second, info.zone);
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
        throw std::runtime_error("segment " + std::to_string(row.id) + " has a malformed geometry");
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
  if (!(max_distance_m > 0.0)) {
    return fail<NearestRoad>(StatusCode::invalid_argument, "max_distance_m must be > 0");
  }
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
      road.highway = attributes.column_text_view(at[C::highway]);
      road.name = attributes.column_text_view(at[C::name]);
      road.segment_length_m = attributes.column_double(at[C::length_m]);
    }
    attributes.reset();
    return Result<NearestRoad>{Status{}, std::move(road)};
  } catch (const std::exception& e) {
    impl_->queries.candidates.reset();
    impl_->queries.attributes.reset();
    return fail<NearestRoad>(StatusCode::corrupt_database, impl_->info.path + ": " + e.what());
  }
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
      throw std::runtime_error("segment " + std::to_string(fid) + " has a malformed geometry");
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
    return fail<RoadHeading>(StatusCode::corrupt_database, impl_->info.path + ": " + e.what());
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

}  // namespace roadcross
