// The inside of roadcross::Map, shared by the runtime's translation units (map.cpp for opening
// and geometry queries, assess.cpp for the cost terms). Not installed.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "polyline.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross {

namespace detail {

/// Bounds of the per-call search distances (AssessOptions::max_distance_m, nearest's and
/// road_heading's max_distance_m; BetterPlaceOptions::search_radius_m), metres: beyond them a
/// query reads a whole country's segments.
inline constexpr double kMaxSearchDistanceM = 100000.0;
inline constexpr double kMaxWalkingRadiusM = 10000.0;

/// `text` with every byte sequence that is not valid UTF-8 replaced by U+FFFD: text read from
/// a map (names, tags, notes, metadata) reaches JSON, Python and ROS, which all need UTF-8.
/// ASCII text (almost every value) is returned unchanged without a scan beyond its bytes.
std::string valid_utf8(std::string_view text);

/// A segment row that cannot be right; becomes StatusCode::corrupt_segment at the API boundary.
class corrupt_segment_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// "segment FID: WHAT" for corrupt_segment_error messages.
std::string segment_problem(std::int64_t fid, const std::string& what);

/// Throws corrupt_segment_error unless every point of segment `fid`'s geometry is finite and
/// inside its R*Tree box (SQLite rounds the box outwards to float32, so a correct box holds its
/// segment exactly): a box that does not hold its segment would answer about another road.
void check_in_box(std::int64_t fid, const std::vector<schema::PlanePoint>& points, double min_x,
                  double max_x, double min_y, double max_y);

/// How much work one API call may make SQLite do, counted by SQLite's progress handler (every
/// kStepsPerTick virtual-machine instructions): a bound on hostile maps whose statements would
/// run for ever. Restarted at the start of every public Map call; far above what a query of
/// the largest bundled map needs (docs/reliability.md, "Maps as untrusted input").
struct WorkBudget {
  static constexpr int kStepsPerTick = 4096;
  static constexpr std::uint64_t kTicksPerCall = 100000;  // ~4e8 instructions, seconds of work
  std::uint64_t ticks_left = kTicksPerCall;
  void restart() noexcept { ticks_left = kTicksPerCall; }
};

/// The Status for an exception caught at the API boundary: corrupt_segment for a damaged row,
/// corrupt_database for an interrupted (too much work), oversized or malformed read.
Status status_of(const std::exception& error, const std::string& path);

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

/// Suitability thresholds as recorded by the build (param.suitability.*), else the thesis'
/// defaults.
struct Thresholds {
  double valid_distance_m = 10.0;
  double threshold = 20.0;
  /// LIMITED_VISIBILITY forbids crossing (the build's sight.limited_visibility_unsuitable); in
  /// cost mode the build has already added its penalty to the rank.
  bool limited_visibility_unsuitable = true;
  /// The robot profile's highest climbable kerb (param.suitability.max_kerb_height_m), metres;
  /// 1 m (no limit) for maps built without it.
  double max_kerb_height_m = 1.0;
};

/// The thresholds recorded in `info`'s metadata; a recorded value that is not a finite number
/// in range is an error naming the key (returned as a non-ok Status).
Status thresholds_from(const MapInfo& info, Thresholds& out);

/// invalid_argument unless every per-call threshold is finite and in range.
Status check_assess_options(const AssessOptions& options);

/// An edge of a region segment's polyline: its start and its vector, grid metres, and its
/// squared length, m^2 (computed once per query, not once per sample).
struct RegionEdge {
  double start_x = 0.0, start_y = 0.0, dx = 0.0, dy = 0.0;
  /// 1 / (dx^2 + dy^2), 1/m^2; 0 for an edge of zero length (its start is its nearest point).
  double inverse_length_sq_per_m2 = 0.0;
};

/// One segment near an uncertain position, with its geometry and bounding box (grid metres).
struct RegionSegment {
  std::int64_t id = 0;
  std::vector<schema::PlanePoint> points;
  std::vector<RegionEdge> edges;
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  std::size_t sample_count = 0;       ///< samples of the region whose nearest segment this is
  bool centreline_in_region = false;  ///< its centreline runs through the region's ellipse
  /// Per edge: the axial difference of its direction from the fix's, radians; -1 until needed.
  std::vector<double> edge_spread_rad;
};

/// A region segment's box and its distance from the fix (metres), in the order the
/// nearest-segment search visits them: by that distance, then by index into region_segments.
struct BoxCandidate {
  double from_fix_m = 0.0;
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  std::size_t index = 0;
};

/// The geometry of an uncertain position's region: which segments it touches, how much of its
/// probability lies nearest to each, and how the road's direction varies over it.
struct RegionGeometry {
  double region_probability = 0.95;
  double semi_major_m = 0.0, semi_minor_m = 0.0, major_axis_yaw_rad = 0.0;
  std::size_t sample_count = 0;   ///< equal-probability samples of the region
  std::size_t segment_count = 0;  ///< the first this many of Impl::region_segments are used
  std::size_t fix_index = 0;      ///< the fix's own segment among them
  double heading_spread_rad = 0.0;
};

/// The `assessment` statement's SQL (kAssessColumns, in its order) with the columns that only
/// describe a place (its class, curvature, terrain, speed, sight lines, ...) selected as NULL.
std::string region_verdict_sql(int schema_version);

/// How much wider than an exact locate's the first search box must be for the region of `u`
/// to lie inside it whenever the nearest road is within that exact first box: twice the
/// region's semi-major axis, metres (0 for an invalid `u`).
double region_reach_m(const PositionUncertainty& u);

/// `u` checked (finite, positive definite, probability in (0, 1)) and turned into the map's
/// grid at `fix` (Frame::enu is rotated by the meridian convergence there). invalid_argument
/// otherwise; throws std::exception when `fix` is outside the zone's projection.
Status uncertainty_in_grid(const PositionUncertainty& u, const geo::UtmZone& zone,
                           const schema::PlanePoint& fix, PositionUncertainty& grid);

}  // namespace detail

struct Map::Impl {
  std::unique_ptr<detail::WorkBudget> budget;  // owned here, given to SQLite's progress handler
  sqlite::Database db;
  MapInfo info;
  detail::Queries queries;
  detail::Thresholds thresholds;
  std::vector<schema::PlanePoint> scratch;  // reused geometry buffer: no allocation per query
  std::vector<schema::PlanePoint> best_geometry;
  // The rows (id, geometry) of locate's last R*Tree query, the first located_rows, whose box
  // was located_at +- located_half_m; then the region of an uncertain position, which reuses
  // them when its box lies inside that one (one R*Tree query instead of two).
  std::vector<detail::RegionSegment> region_segments;
  std::size_t located_rows = 0;
  schema::PlanePoint located_at;
  double located_half_m = 0.0;
  std::vector<detail::BoxCandidate> by_box_distance;
  // One ring of the region's samples against its candidate segments: the squared distance
  // (m^2) and nearest edge of each, a row of samples per candidate in by_box_distance order.
  std::vector<double> ring_distance_sq_m2;
  std::vector<std::uint32_t> ring_nearest_edge;

  /// The `assessment` row of one segment with its descriptive columns (those no verdict reads)
  /// selected as NULL: what judge_region feeds the same judge for the region's segments.
  sqlite::Statement region_verdict;

  Impl(std::unique_ptr<detail::WorkBudget> work_budget, sqlite::Database&& database,
       MapInfo&& map_info, detail::Thresholds map_thresholds)
      : budget(std::move(work_budget)),
        db(std::move(database)),
        info(std::move(map_info)),
        queries(db, info.schema_version),
        thresholds(map_thresholds),
        region_verdict(db.prepare(detail::region_verdict_sql(info.schema_version))) {}

  /// The position in the map's UTM zone, or invalid_argument.
  Status to_plane(const Position& position, schema::PlanePoint& out) const noexcept;

  /// The nearest segment within max_distance_m (> 0, checked by the caller): fills the
  /// segment id, query, closest point and distance of `road` (not its attributes), and leaves
  /// the segment's geometry in best_geometry. Its first search box is widened by
  /// `region_reach_m` (see region_reach_m()) so that region_geometry can reuse its rows.
  /// invalid_argument or not_found otherwise; throws on an SQLite error or a malformed geometry.
  Status locate(const Position& position, double max_distance_m, NearestRoad& road,
                double region_reach_m = 0.0);

  /// The side of the centreline `road` (just located: its geometry is in best_geometry) the
  /// query stands on: +1 left of the way's direction, -1 right, 0 on the centreline (within
  /// 1 mm), where the side is unknown.
  int side_of(const NearestRoad& road) const noexcept;

  /// The road's direction (ENU yaw, radians) at `at` on segment `segment_id`, whose geometry is
  /// in best_geometry: polyline_direction_rad, except at the segment's first or last vertex
  /// where exactly one other segment continues the road (a graph node of degree 2), which
  /// gives the bisector of the two segments' directions there. Throws like locate.
  double direction_at(std::int64_t segment_id, const detail::PolylineProjection& at);

  /// The segments whose box meets the box fix +- (half_x_m, half_y_m), with their geometry
  /// and box, into the first (returned) count of region_segments: locate's rows when its last
  /// query at `fix` covered that box, else an R*Tree query. Throws like locate.
  std::size_t region_rows(const schema::PlanePoint& fix, double half_x_m, double half_y_m);

  /// The region of `uncertainty` around the located fix `road` (locate called): fills
  /// region_segments and `out`. invalid_argument for a covariance that is not finite and
  /// positive definite or a probability outside (0, 1); throws like locate.
  Status region_geometry(const PositionUncertainty& uncertainty, const NearestRoad& road,
                         detail::RegionGeometry& out);

  /// Judges the segments of the region of `uncertainty` around the fix already judged in `a`,
  /// fills a.region and narrows a's verdict to what holds over the whole region: suitable only
  /// when every segment of it is and all are on the fix's road. Fails like region_geometry.
  Status judge_region(const PositionUncertainty& uncertainty, Assessment& a);
};

}  // namespace roadcross
