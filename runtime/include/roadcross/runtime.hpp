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

/// A query position: UTM easting/northing in the map's zone, or WGS84 latitude/longitude.
struct Position {
  enum class Kind { utm, wgs84 };
  Kind kind = Kind::utm;
  double first = 0.0;   ///< easting_m or lat_deg
  double second = 0.0;  ///< northing_m or lon_deg

  static Position utm(double easting_m, double northing_m) noexcept {
    return {Kind::utm, easting_m, northing_m};
  }
  static Position wgs84(double lat_deg, double lon_deg) noexcept {
    return {Kind::wgs84, lat_deg, lon_deg};
  }
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
  /// Extent of all segments in the map's UTM zone, metres.
  double min_easting_m = 0.0, min_northing_m = 0.0, max_easting_m = 0.0, max_northing_m = 0.0;
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
};

/// Per-call overrides of the DB's suitability thresholds (unset = the DB's value, recorded at
/// build time as param.suitability.*, or the thesis' default for older DBs).
struct AssessOptions {
  std::optional<double> valid_distance_m;  ///< a position is valid within this of a centreline
  std::optional<double> threshold;         ///< suitable when score + context_score >= this
  double max_distance_m = 1000.0;          ///< how far to look for the nearest road, metres
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
  std::string override_note;  ///< the operator's note when an override applies
  /// Reason codes: the segment's (NEAR_JUNCTION, SHARP_BEND, BUSY_ROAD, NOT_CROSSABLE_CLASS,
  /// TUNNEL, CREST_OR_DIP, ...) plus TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE.
  std::vector<std::string> reasons;
};

struct BetterPlaceOptions {
  double search_radius_m = 100.0;  ///< walking distance along the road, metres, > 0
  std::size_t max_candidates = 5;  ///< at most this many, best first
  AssessOptions assess;            ///< thresholds applied to every candidate
};

/// A place to cross instead, reached by walking along the road on the robot's side.
struct Candidate {
  PlanePoint point;  ///< where to stand: same side, same offset from the centreline
  double walking_distance_m = 0.0;
  std::int64_t segment_id = 0;
  bool suitable = false;
  int score = 0;                      ///< score + context_score
  bool designated_crossing = false;   ///< a designated crossing within 5 m of the place
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
  /// TOO_FAR_FROM_ROAD first among the reasons when not valid.
  Result<Assessment> assess_segment(std::int64_t segment_id,
                                    const AssessOptions& options = {}) noexcept;

  /// Up to max_candidates places within search_radius_m of walking along the road (through the
  /// road graph, on the robot's side, never across), ranked: suitable first, then designated
  /// crossings, then score + context, then walking distance. Segments near a junction are not
  /// offered. An empty list comes with the reason.
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
