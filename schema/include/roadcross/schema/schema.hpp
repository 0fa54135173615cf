// The roadcross database contract. A roadcross DB is a GeoPackage 1.3 file; everything
// roadcross-specific is named here so that the writer and the reader cannot drift apart.
#pragma once

#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace roadcross::schema {

/// Version of the roadcross tables inside the GeoPackage. Bump on any change a reader must know
/// about (a column added, renamed or whose meaning changed). Readers accept exactly the versions
/// in [kOldestReadableVersion, kSchemaVersion].
/// 2: the sight distance columns. Version 1 DBs stay readable: the runtime reads
/// no sight column, and a version 1 DB simply never carries LIMITED_VISIBILITY.
/// 3 (issue 28): kerb, kerb_height_m, crossing_island, sidewalk_left, sidewalk_right. Older DBs
/// stay readable: the runtime reads NULL (unknown) for them, and unknown never forbids.
inline constexpr int kSchemaVersion = 4;
inline constexpr int kOldestReadableVersion = 1;

/// GeoPackage fixes these two SQLite header fields (spec 1.3: 'GPKG' and 10300).
inline constexpr std::int32_t kGpkgApplicationId = 0x47504B47;
inline constexpr std::int32_t kGpkgUserVersion = 10300;

inline constexpr std::string_view kSegmentsTable = "segments";
inline constexpr std::string_view kGeometryColumn = "geom";
inline constexpr std::string_view kSegmentsRtree = "rtree_segments_geom";
inline constexpr std::string_view kMetadataTable = "roadcross_metadata";
/// Designated crossings (and informal ones, flagged): a POINT feature table in the same CRS,
/// with its own R*Tree. Columns: crossing_columns().
inline constexpr std::string_view kCrossingsTable = "crossings";
inline constexpr std::string_view kCrossingsRtree = "rtree_crossings_geom";

/// Keys of the roadcross_metadata(id, key, value) table (key unique; id only because GeoPackage
/// wants an INTEGER primary key).
namespace meta {
inline constexpr std::string_view kSchemaVersion = "schema_version";
inline constexpr std::string_view kToolVersion = "tool_version";
inline constexpr std::string_view kUtmZone = "utm_zone";          // 1..60
inline constexpr std::string_view kUtmNorthern = "utm_northern";  // "1" or "0"
inline constexpr std::string_view kEpsg = "epsg";                 // 326zz / 327zz
inline constexpr std::string_view kSegmentCount = "segment_count";
inline constexpr std::string_view kAttribution = "attribution";
/// Country whose implicit speed limits filled untagged ways ("CZ", ..., "default").
inline constexpr std::string_view kContextCountry = "context_country";
inline constexpr std::string_view kCrossingCount = "crossing_count";
/// The map's identity: SHA-256 (64 lower-case hex digits) of its content, as
/// roadcross::mapcheck defines it (docs/embedding.md, "The map's identity").
inline constexpr std::string_view kMapId = "map_id";
/// The newest OSM object's timestamp, ISO 8601 UTC ("2026-03-01T12:00:00Z"); absent when the
/// OSM input carries no timestamps.
inline constexpr std::string_view kOsmTimestamp = "osm_timestamp";
/// "content.<table>.<column>": SHA-256 of one column's values, from which map_id is computed;
/// lets verify name the column that changed.
inline constexpr std::string_view kContentDigestPrefix = "content.";
/// The map's coverage, so that a set of maps picks the one for a position without querying
/// each map's index: the segments' extent in the map's UTM grid (metres, as gpkg_contents'
/// min_x..max_y of segments) and the WGS84 box of that rectangle (degrees,
/// geo::wgs84_box_of_utm_rectangle). Maps written before these keys: the runtime computes both
/// on open from gpkg_contents.
inline constexpr std::string_view kCoverageMinEasting = "coverage.min_easting_m";
inline constexpr std::string_view kCoverageMinNorthing = "coverage.min_northing_m";
inline constexpr std::string_view kCoverageMaxEasting = "coverage.max_easting_m";
inline constexpr std::string_view kCoverageMaxNorthing = "coverage.max_northing_m";
inline constexpr std::string_view kCoverageMinLat = "coverage.min_lat_deg";
inline constexpr std::string_view kCoverageMinLon = "coverage.min_lon_deg";
inline constexpr std::string_view kCoverageMaxLat = "coverage.max_lat_deg";
inline constexpr std::string_view kCoverageMaxLon = "coverage.max_lon_deg";
/// Parameters are stored as "param.<name>"; inputs as "input.<n>.path", "input.<n>.sha256",
/// "input.<n>.kind".
inline constexpr std::string_view kParamPrefix = "param.";
inline constexpr std::string_view kInputPrefix = "input.";
/// The parameters the runtime reads back: the map's default thresholds of the verdict.
inline constexpr std::string_view kValidDistanceParam = "param.suitability.valid_distance_m";
inline constexpr std::string_view kThresholdParam = "param.suitability.threshold";
inline constexpr std::string_view kLimitedVisibilityUnsuitableParam =
    "param.sight.limited_visibility_unsuitable";
/// The robot profile's highest climbable kerb, metres (schema version 3; absent: no limit).
inline constexpr std::string_view kMaxKerbHeightParam = "param.suitability.max_kerb_height_m";
}  // namespace meta

/// A column of a roadcross table: its name, SQL type, what it means (with unit) and the schema
/// version that added it (older maps lack it; readers select NULL in its place).
struct Column {
  std::string_view name;
  std::string_view sql_type;
  std::string_view description;
  int since_version = 1;
};

/// The attribute columns of `segments`, by name. The enumerators are the column names and their
/// order is the table's order (after fid and geom): code reads and writes columns through these
/// names, never through numbers.
enum class SegmentColumn : std::uint8_t {
  osm_way_id,
  highway,
  name,
  length_m,
  from_node_id,
  to_node_id,
  oneway,
  tunnel,
  bridge,
  class_cost,
  junction_distance_m,
  radius_m,
  curvature_level,
  curvature_cost,
  elevation_m,
  slope_deg,
  grade_percent,
  tpi_small_m,
  tpi_large_m,
  landform,
  elevation_cost,
  maxspeed_kmh,
  lanes,
  width_m,
  context_score,
  crossing_distance_m,
  context_defaulted,
  override_note,
  override_no_crossing,
  override_force_suitable,
  rank,
  score,
  reasons,
  sight_forward_m,
  sight_backward_m,
  sight_min_m,
  required_sight_m,
  kerb,
  kerb_height_m,
  crossing_island,
  sidewalk_left,
  sidewalk_right,
  suitable,
};
inline constexpr std::size_t kSegmentColumnCount =
    static_cast<std::size_t>(SegmentColumn::suitable) + 1;

/// The attribute columns of `segments` in their table order (after fid and geom); entry i is
/// the column of enumerator i.
const std::vector<Column>& segment_columns();

/// The spec of one segments column.
const Column& column_spec(SegmentColumn column);

/// A SELECT list of named segments columns, and where each one lands in a statement's result.
/// Columns that `schema_version` does not have are selected as NULL, so that one reader serves
/// every readable version.
class SegmentSelection {
 public:
  /// `columns`: what to read, in result order, starting at result position `first_position`
  /// (the columns before it are the caller's own, e.g. fid and geom).
  SegmentSelection(std::initializer_list<SegmentColumn> columns, int first_position = 0);

  /// "a.name1, a.name2, ..." with `table_alias` ("" for none) and NULL for absent columns.
  std::string sql(std::string_view table_alias, int schema_version) const;

  /// The result position of `column`; throws std::logic_error when it was not selected.
  int operator[](SegmentColumn column) const;

 private:
  std::vector<SegmentColumn> columns_;
  std::vector<int> position_;  // by enumerator; -1 where not selected
};

/// The attribute columns of `crossings` in their table order (after fid and geom).
const std::vector<Column>& crossing_columns();

/// EPSG code of WGS84 / UTM zone `zone` (1..60), north or south.
int utm_epsg(int zone, bool northern);

/// OGC WKT 1 definition of that CRS, as GeoPackage's gpkg_spatial_ref_sys wants it.
std::string utm_wkt(int zone, bool northern);

/// SQL statements that create an empty roadcross GeoPackage for the given UTM zone.
/// `last_change` fills gpkg_contents.last_change (ISO 8601); it is an input so that the output
/// stays deterministic.
std::vector<std::string> create_statements(int zone, bool northern, std::string_view last_change);

/// SQL statements that create the GeoPackage R*Tree triggers for segments.geom and
/// crossings.geom. Run after the bulk load (the triggers call ST_* functions that plain SQLite
/// does not provide).
std::vector<std::string> rtree_trigger_statements();

}  // namespace roadcross::schema
