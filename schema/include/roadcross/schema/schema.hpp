// The roadcross database contract. A roadcross DB is a GeoPackage 1.3 file; everything
// roadcross-specific is named here so that the writer and the reader cannot drift apart.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace roadcross::schema {

/// Version of the roadcross tables inside the GeoPackage. Bump on any change a reader must know
/// about (a column added, renamed or whose meaning changed). Readers accept exactly the versions
/// in [kOldestReadableVersion, kSchemaVersion].
/// 2 (issue 11): the sight distance columns. Version 1 DBs stay readable: the runtime reads
/// no sight column, and a version 1 DB simply never carries LIMITED_VISIBILITY.
inline constexpr int kSchemaVersion = 2;
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
/// Parameters are stored as "param.<name>"; inputs as "input.<n>.path", "input.<n>.sha256",
/// "input.<n>.kind".
inline constexpr std::string_view kParamPrefix = "param.";
inline constexpr std::string_view kInputPrefix = "input.";
}  // namespace meta

/// A column of the segments table: its name, SQL type and what it means (with unit).
struct Column {
  std::string_view name;
  std::string_view sql_type;
  std::string_view description;
};

/// The attribute columns of `segments` in their table order (after fid and geom).
const std::vector<Column>& segment_columns();

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
