// The inside of roadcross::Map, shared by the runtime's translation units (map.cpp for opening
// and geometry queries, assess.cpp for the cost terms). Not installed.
#pragma once

#include <string>
#include <vector>

#include "polyline.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross {

namespace detail {

/// Prepared once per Map, reused by every query (SQLite's advice for hot paths).
struct Queries {
  sqlite::Statement candidates;  ///< segments whose R*Tree box meets a query box
  sqlite::Statement attributes;  ///< identity of one segment (nearest)
  /// Identity and every cost column of one segment, in one row read (assess).
  sqlite::Statement assessment;
  /// Stepped once and never reset: an R*Tree cursor that stays open. SQLite's R*Tree closes its
  /// handle on the node table when its last cursor closes, and reopening it compiles a
  /// statement (a tenth of assess's time); with this cursor open, every query reuses it.
  sqlite::Statement rtree_holder;
  /// Segments (with their end nodes) whose R*Tree box meets a query box (road_heading at a
  /// segment's end vertex).
  sqlite::Statement segments_at;

  /// `schema_version`: the map's; columns it lacks read as NULL.
  Queries(sqlite::Database& db, int schema_version);
};

/// What assess reads of a segment (the `assessment` statement).
extern const schema::SegmentSelection kAssessColumns;
/// What nearest() reads of a segment: its identity (the `attributes` statement).
extern const schema::SegmentSelection kIdentityColumns;
/// The end nodes read after fid and geom (the `segments_at` statement).
extern const schema::SegmentSelection kEndNodeColumns;

/// Suitability thresholds as recorded by the build (param.suitability.*), else the thesis' defaults.
struct Thresholds {
  double valid_distance_m = 10.0;
  double threshold = 20.0;
  /// LIMITED_VISIBILITY forbids crossing (the build's sight.limited_visibility_unsuitable); in
  /// cost mode the build has already added its penalty to the rank.
  bool limited_visibility_unsuitable = true;
};

Thresholds thresholds_from(const MapInfo& info);

}  // namespace detail

struct Map::Impl {
  sqlite::Database db;
  MapInfo info;
  detail::Queries queries;
  detail::Thresholds thresholds;
  std::vector<schema::PlanePoint> scratch;  // reused geometry buffer: no allocation per query
  std::vector<schema::PlanePoint> best_geometry;

  Impl(sqlite::Database&& database, MapInfo&& map_info)
      : db(std::move(database)),
        info(std::move(map_info)),
        queries(db, info.schema_version),
        thresholds(detail::thresholds_from(info)) {}

  /// The position in the map's UTM zone, or invalid_argument.
  Status to_plane(const Position& position, schema::PlanePoint& out) const noexcept;

  /// The nearest segment within max_distance_m (> 0, checked by the caller): fills the
  /// segment id, query, closest point and distance of `road` (not its attributes), and leaves
  /// the segment's geometry in best_geometry. invalid_argument or not_found otherwise; throws
  /// on an SQLite error or a malformed geometry.
  Status locate(const Position& position, double max_distance_m, NearestRoad& road);

  /// The road's direction (ENU yaw, radians) at `at` on segment `segment_id`, whose geometry is
  /// in best_geometry: polyline_direction_rad, except at the segment's first or last vertex
  /// where exactly one other segment continues the road (a graph node of degree 2), which
  /// gives the bisector of the two segments' directions there. Throws like locate.
  double direction_at(std::int64_t segment_id, const detail::PolylineProjection& at);
};

}  // namespace roadcross
