// The roadcross runtime: opens a roadcross GeoPackage read-only and answers queries about the
// road network in microseconds. Depends on SQLite and GeographicLib only; this header includes
// neither. Every call is noexcept and reports failure through Status.
//
// Threading: one Map holds one SQLite connection and its prepared statements; use one Map per
// thread (opening is cheap). Map objects share no state of their own; SQLite's process-wide
// memory statistics are the one shared lock left (see disable_sqlite_memory_statistics).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/geo_box.hpp"

namespace roadcross {

enum class StatusCode {
  ok,
  file_not_found,    ///< the path does not exist or is not readable
  not_a_database,    ///< not SQLite, not a GeoPackage, or not written by roadcross-build
  wrong_version,     ///< a roadcross DB of a schema version this runtime cannot read
  corrupt_database,  ///< a roadcross DB whose content breaks the contract
  invalid_argument,  ///< NaN, out-of-range latitude/longitude, position outside the map's zone
  not_found,         ///< no road in the map near enough to answer
  internal,          ///< an unexpected SQLite error
  /// One segment's row cannot be right (a non-finite or out-of-range value, a negative length,
  /// an unknown reason code, an index box that does not contain the segment, flags that
  /// contradict the reasons): the map is damaged there, so no verdict is given. The message
  /// names the segment (fid and OSM way) and what is wrong.
  corrupt_segment,
};

const char* to_string(StatusCode code) noexcept;

struct Status {
  StatusCode code = StatusCode::ok;
  std::string message;  ///< what went wrong and what to do about it; empty when ok
  bool ok() const noexcept { return code == StatusCode::ok; }
};

/// A value or the reason there is none.
template <typename T>
struct Result {
  Status status;
  std::optional<T> value;
  bool ok() const noexcept { return status.ok(); }
  const T& operator*() const { return *value; }
  T& operator*() { return *value; }
  const T* operator->() const { return &*value; }
  T* operator->() { return &*value; }
};

/// How far a position may be off: the covariance of its error, a 2x2 symmetric matrix in m^2,
/// and the share of that Gaussian which makes the region of places the robot may be at
/// (docs/runtime.md, "Position uncertainty"). A GNSS receiver's covariance is in true ENU
/// (east, north); the map's grid is turned against it by the meridian convergence, which
/// the runtime applies (Frame::enu). A covariance already in the map's grid is Frame::grid.
struct PositionUncertainty {
  enum class Frame { grid, enu };
  Frame frame = Frame::grid;
  double east_east_m2 = 0.0;    ///< variance along east, m^2, > 0
  double east_north_m2 = 0.0;   ///< covariance of east and north, m^2
  double north_north_m2 = 0.0;  ///< variance along north, m^2, > 0; the matrix positive definite
  /// Probability mass of the region (the ellipse holding this share of the Gaussian), in
  /// (0, 1); 0.95 by default.
  double region_probability = 0.95;

  /// The same standard deviation `sigma_m` (metres, finite, > 0) in every direction. A
  /// negative sigma keeps its sign in the variances, so that the queries reject it.
  static PositionUncertainty circular(double sigma_m, double region_probability = 0.95) noexcept {
    const double variance_m2 = (sigma_m < 0.0 ? -sigma_m : sigma_m) * sigma_m;
    return {Frame::grid, variance_m2, 0.0, variance_m2, region_probability};
  }
  /// A covariance in true ENU (e.g. NavSatFix.position_covariance's first 2x2 block), m^2.
  static PositionUncertainty enu(double east_east_m2, double east_north_m2, double north_north_m2,
                                 double region_probability = 0.95) noexcept {
    return {Frame::enu, east_east_m2, east_north_m2, north_north_m2, region_probability};
  }
};

/// A query position: UTM easting/northing, or WGS84 latitude/longitude, with an optional
/// uncertainty (unset: the position is taken as exact).
struct Position {
  enum class Kind { utm, wgs84 };
  Kind kind = Kind::utm;
  double first = 0.0;   ///< easting_m or lat_deg
  double second = 0.0;  ///< northing_m or lon_deg
  /// The UTM position's zone; zone 0 (the default) means the zone of the map asked. A Map
  /// reprojects a position given in another zone; a MapSet, whose maps may lie in several
  /// zones, takes a UTM position only with its zone.
  geo::UtmZone zone{0, true};
  std::optional<PositionUncertainty> uncertainty;

  /// Easting and northing in the zone of the map asked (metres).
  static Position utm(double easting_m, double northing_m) noexcept {
    return {Kind::utm, easting_m, northing_m, geo::UtmZone{0, true}, std::nullopt};
  }
  /// Easting and northing in `zone` (metres; zone 1..60).
  static Position utm(double easting_m, double northing_m, geo::UtmZone zone) noexcept {
    return {Kind::utm, easting_m, northing_m, zone, std::nullopt};
  }
  static Position wgs84(double lat_deg, double lon_deg) noexcept {
    return {Kind::wgs84, lat_deg, lon_deg, geo::UtmZone{0, true}, std::nullopt};
  }
  /// This position with a circular uncertainty of `sigma_m` (metres, finite, > 0).
  Position with_sigma(double sigma_m, double region_probability = 0.95) const noexcept {
    Position p = *this;
    p.uncertainty = PositionUncertainty::circular(sigma_m, region_probability);
    return p;
  }
  /// This position with the given uncertainty.
  Position with_uncertainty(const PositionUncertainty& u) const noexcept {
    Position p = *this;
    p.uncertainty = u;
    return p;
  }
};

/// The region of an uncertain position and what the answer is over it (docs/runtime.md,
/// "Position uncertainty").
struct UncertaintyRegion {
  double region_probability = 0.95;  ///< the Gaussian mass the region holds
  /// The region's ellipse in the map's grid: semi-axes (metres) and the direction of the major
  /// axis (ENU yaw in the grid, radians, (-pi/2, pi/2]).
  double semi_major_m = 0.0, semi_minor_m = 0.0, major_axis_yaw_rad = 0.0;
  /// Every segment that is the nearest road somewhere in the region or whose centreline runs
  /// through it, the nearest one at the fix itself first.
  std::vector<std::int64_t> segment_ids;
  bool same_road = true;  ///< all of them belong to the road of the fix (same OSM way or name)
  /// Share of the region's probability (Gaussian weights, conditional on being in the region)
  /// on places whose segment is suitable, [0, 1].
  double suitable_share = 0.0;
  /// The largest difference between the road's direction at the fix and at any place of the
  /// region, as an axis (a road drawn the other way is the same axis), radians, [0, pi/2].
  double heading_spread_rad = 0.0;
};

struct PlanePoint {
  double easting_m = 0.0;
  double northing_m = 0.0;
};

struct MapInfo {
  std::string path;
  int schema_version = 0;
  std::string tool_version;
  geo::UtmZone zone;
  int epsg = 0;
  std::int64_t segment_count = 0;
  /// Extent of all segments in the map's UTM zone, metres (the coverage.* metadata, else
  /// gpkg_contents' extent of segments, else the R*Tree's).
  double min_easting_m = 0.0, min_northing_m = 0.0, max_easting_m = 0.0, max_northing_m = 0.0;
  /// The map's identity: SHA-256 of its content, 64 lower-case hex digits (roadcross verify
  /// recomputes it); empty for a map built before map_id existed.
  std::string map_id;
  /// The newest OSM object's timestamp, ISO 8601 UTC ("2026-03-01T12:00:00Z"): how current the
  /// map's roads are. Empty when the OSM input carried no timestamps.
  std::string osm_timestamp;
  /// The same extent's WGS84 box, degrees (coverage.*_deg metadata, else computed on open with
  /// geo::wgs84_box_of_utm_rectangle).
  geo::LatLonBox coverage_wgs84;
  /// True when the map stores its coverage (coverage.* metadata); false for maps written
  /// before it, whose coverage was computed on open.
  bool coverage_stored = false;
  /// Every row of the metadata table (schema version, parameters, inputs), sorted by key.
  std::vector<std::pair<std::string, std::string>> metadata;
};

/// The road centreline nearest to a position.
struct NearestRoad {
  std::int64_t segment_id = 0;
  std::int64_t osm_way_id = 0;
  std::string highway;  ///< OSM highway=* value
  std::string name;     ///< empty when the way has no name
  PlanePoint query;     ///< the query position in the map's UTM zone
  PlanePoint closest;   ///< nearest point on the segment's centreline
  double distance_m = 0.0;
  double segment_length_m = 0.0;
};

/// The road direction at the nearest point and the heading that crosses it.
struct RoadHeading {
  NearestRoad road;
  /// Direction of the road at the nearest point, in the direction the OSM way is drawn,
  /// ENU yaw in the map's UTM grid frame, radians (-pi, pi].
  double road_heading_rad = 0.0;
  /// Perpendicular to the road, pointing from the query position's side across it, ENU yaw in
  /// the UTM grid frame, radians (-pi, pi]. On the centreline itself (on_centreline) the side
  /// is unknown and the right-hand normal of the way direction is returned.
  double crossing_heading_rad = 0.0;
  /// The same two directions as compass bearings (degrees, [0, 360), grid north).
  double road_bearing_deg = 0.0;
  double crossing_bearing_deg = 0.0;
  /// Add to a grid yaw to get a yaw relative to true east (see geo::UtmPoint).
  double convergence_rad = 0.0;
  bool on_centreline = false;
  /// Under position uncertainty: how much the road's direction varies over the region (see
  /// UncertaintyRegion::heading_spread_rad), radians, [0, pi/2].
  std::optional<double> heading_spread_rad;
};

/// Per-call overrides of the DB's suitability thresholds (unset = the DB's value, recorded at
/// build time as param.suitability.*, or the thesis' default for older DBs).
/// Every value must be finite (NaN and infinities are invalid_argument).
struct AssessOptions {
  /// A position is valid within this of a centreline, metres, >= 0.
  std::optional<double> valid_distance_m;
  /// Suitable when score + context_score >= this (a score, unitless, finite).
  std::optional<double> threshold;
  /// How far to look for the nearest road, metres, in (0, 100 000].
  double max_distance_m = 1000.0;
  /// The robot's capability: the highest kerb it climbs, metres, finite and >= 0. A known kerb
  /// higher than this makes a place unsuitable (KERB_TOO_HIGH); an unknown kerb never does.
  /// Unset: the map profile's param.suitability.max_kerb_height_m (1 m, i.e. no limit, in maps
  /// built without a robot profile and in DBs older than schema version 3).
  std::optional<double> max_kerb_height_m;
};

/// Is this a place to cross, and why not. Cost terms are absent (nullopt) where the DB has none
/// (e.g. no elevation data was given to the build).
struct Assessment {
  NearestRoad road;
  bool valid = false;     ///< within valid_distance_m of the road centreline
  bool suitable = false;  ///< valid, score + context_score >= threshold, and not forbidden
  double valid_distance_m = 10.0;
  double threshold = 20.0;
  std::optional<int> class_cost, curvature_level, curvature_cost, elevation_cost;
  std::optional<double> junction_distance_m, radius_m, crossing_distance_m;
  std::optional<double> maxspeed_kmh, width_m;
  std::optional<int> lanes;
  std::optional<std::string> landform;
  std::optional<int> rank, score, context_score;
  /// Sight distances along the road (forward: in the OSM way's direction) and the distance a
  /// crossing needs, metres; empty in tunnels and in DBs older than schema version 2.
  std::optional<double> sight_forward_m, sight_backward_m, sight_min_m, required_sight_m;
  bool tunnel = false;
  /// What a wheeled robot meets here (schema version 3; empty in older DBs and where OSM says
  /// nothing): the kerb=* value of the highest kerb at a crossing within 5 m, its height in
  /// metres (kerb:height, else the value's usual height: docs/cost-model.md), a refuge island,
  /// and a pavement on each side of the OSM way's direction.
  std::optional<std::string> kerb;
  std::optional<double> kerb_height_m;
  std::optional<bool> crossing_island;
  std::optional<bool> sidewalk_left, sidewalk_right;
  /// The robot's kerb capability the judgement used (AssessOptions or the map profile), metres.
  double max_kerb_height_m = 1.0;
  /// The robot's side of the centreline: +1 left of the way's direction, -1 right, 0 unknown
  /// (on the centreline, and in assess_segment). The far side is the other one.
  int robot_side = 0;
  /// A pavement on the far side: true, false (NO_PAVEMENT_FAR_SIDE), unknown.
  std::optional<bool> pavement_far_side;
  std::string override_note;  ///< the operator's note when an override applies
  /// Reason codes: the segment's (NEAR_JUNCTION, SHARP_BEND, BUSY_ROAD, NOT_CROSSABLE_CLASS,
  /// TUNNEL, CREST_OR_DIP, ...) plus TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE,
  /// KERB_TOO_HIGH and NO_PAVEMENT_FAR_SIDE (both make the place unsuitable), and under position
  /// uncertainty POSITION_UNCERTAIN / AMBIGUOUS_ROAD.
  std::vector<std::string> reasons;
  /// Set when the position has an uncertainty: the region and the share on suitable places.
  /// Then `suitable` holds only when the fix's segment and every segment of the region are
  /// suitable and on the same road; the cost terms above stay those of the fix's segment.
  std::optional<UncertaintyRegion> region;
};

struct BetterPlaceOptions {
  double search_radius_m = 100.0;  ///< walking distance along the road, metres, (0, 10 000]
  std::size_t max_candidates = 5;  ///< at most this many, best first
  AssessOptions assess;            ///< thresholds applied to every candidate
};

/// A place to cross instead, reached by walking along the road on the robot's side.
struct Candidate {
  /// Where to stand: the robot's side, at its offset from the centreline (at least 1 m, at most
  /// the valid distance).
  PlanePoint point;
  double walking_distance_m = 0.0;
  std::int64_t segment_id = 0;
  /// assess's verdict at `point` (the same rule: schema::judge_segment).
  bool suitable = false;
  int score = 0;                     ///< score + context_score
  bool designated_crossing = false;  ///< a designated crossing within 5 m of the place
  /// Under position uncertainty: the share of the region around `point` on suitable places
  /// (UncertaintyRegion::suitable_share); `suitable` then means suitable over that region.
  std::optional<double> suitable_share;
  double crossing_heading_rad = 0.0;  ///< ENU yaw (UTM grid) across the road from that side
  std::vector<std::string> reasons;
};

struct BetterPlaces {
  std::vector<Candidate> candidates;  ///< suitable first, then by score, then by distance
  std::string reason;                 ///< why the list is empty, else empty
};

/// A sentence for a reason code ("the road bends sharply here"), for people.
const char* describe_reason(const std::string& code) noexcept;

/// For hosts that query from several threads: turns off SQLite's memory statistics
/// (SQLITE_CONFIG_MEMSTATUS) for the whole process. With them on (SQLite's default) every
/// allocation inside SQLite takes one global mutex, which two threads assessing at once contend
/// for (docs/performance.md, "Runtime queries": a second thread added 1.25x the throughput
/// with them, 1.78x without, medians of three same-run pairs). A process-wide setting, so the
/// runtime never makes it on its own: call it at start-up, before anything in the process uses
/// SQLite. Returns true when the setting took effect, false when SQLite was already initialised
/// (then nothing changed). Afterwards sqlite3_memory_used() and sqlite3_status() report no memory
/// figures.
bool disable_sqlite_memory_statistics() noexcept;

class Map {
 public:
  /// Opens a roadcross DB read-only and checks that it is a roadcross GeoPackage of a schema
  /// version this runtime reads. The message says what to do otherwise.
  static Result<Map> open(const std::string& path) noexcept;

  Map(Map&&) noexcept;
  Map& operator=(Map&&) noexcept;
  Map(const Map&) = delete;
  Map& operator=(const Map&) = delete;
  ~Map();

  const MapInfo& info() const noexcept;

  /// The position in the map's UTM zone (WGS84 input is projected with GeographicLib).
  Result<PlanePoint> to_utm(const Position& position) const noexcept;

  /// The nearest road segment, searching outwards up to `max_distance_m` (metres, > 0).
  Result<NearestRoad> nearest(const Position& position, double max_distance_m = 1000.0) noexcept;

  /// Whether the position is a suitable place to cross, with every cost term and the reasons.
  Result<Assessment> assess(const Position& position, const AssessOptions& options = {}) noexcept;

  /// The same judgement as assess for a position on the centreline of segment `segment_id`
  /// (distance 0, so valid): for whole-map views (render, export, view) that colour every
  /// segment and must agree with assess. road.query and road.closest are left at 0; not_found
  /// when there is no such segment. At a position off the centreline, assess's answer is this
  /// one with valid = distance <= valid_distance_m, suitable = valid && this suitable, and
  /// TOO_FAR_FROM_ROAD first among the reasons when not valid; and, as the robot's side is
  /// unknown here, without NO_PAVEMENT_FAR_SIDE, which assess adds when the side it stands on
  /// faces a side tagged without a pavement.
  Result<Assessment> assess_segment(std::int64_t segment_id,
                                    const AssessOptions& options = {}) noexcept;

  /// Up to max_candidates places within search_radius_m of walking along the road (through the
  /// road graph, on the robot's side, never across), ranked: suitable first, then designated
  /// crossings, then score + context, then walking distance. Segments near a junction are not
  /// offered. A place with a kerb higher than options.assess.max_kerb_height_m (KERB_TOO_HIGH)
  /// or without a pavement on its far side (NO_PAVEMENT_FAR_SIDE) is not suitable. An empty
  /// list comes with the reason.
  Result<BetterPlaces> better_place(const Position& position,
                                    const BetterPlaceOptions& options = {}) noexcept;

  /// The road's direction at the nearest point and the crossing heading.
  Result<RoadHeading> road_heading(const Position& position,
                                   double max_distance_m = 1000.0) noexcept;

 private:
  struct Impl;
  explicit Map(std::unique_ptr<Impl> impl) noexcept;
  std::unique_ptr<Impl> impl_;
};

}  // namespace roadcross
