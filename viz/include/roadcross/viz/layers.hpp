// What every picture of a map draws: the segments with the runtime's judgement of each, the
// crossings, and the area to show. Read through the runtime (so suitability is assess's rule)
// and plain SQLite (geometries). Errors throw std::runtime_error with a message for the user.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/verdict.hpp"

namespace roadcross::viz {

/// An area in WGS84 degrees, as given on the command line: "MINLON,MINLAT,MAXLON,MAXLAT".
struct LonLatBox {
  double min_lon_deg = 0.0, min_lat_deg = 0.0, max_lon_deg = 0.0, max_lat_deg = 0.0;
};

/// Parses "MINLON,MINLAT,MAXLON,MAXLAT"; throws std::invalid_argument saying what is wrong.
LonLatBox parse_bbox(const std::string& text);

/// An area in the map's UTM zone, metres.
struct UtmBox {
  double min_e_m = 0.0, min_n_m = 0.0, max_e_m = 0.0, max_n_m = 0.0;
  double width_m() const noexcept { return max_e_m - min_e_m; }
  double height_m() const noexcept { return max_n_m - min_n_m; }
  bool intersects(const UtmBox& other) const noexcept;
};

struct SegmentLayer {
  std::int64_t fid = 0;
  std::vector<schema::PlanePoint> line;  ///< UTM metres
  Assessment assessment;                 ///< Map::assess_segment: on the centreline
  /// The road graph's nodes at the segment's two ends (segments sharing one are connected).
  std::int64_t from_node_id = 0, to_node_id = 0;
  /// Why it is not suitable, one code of schema::kReasons (empty when suitable): the first of
  /// schema::judge_segment's forbidding codes, else the robot's rule that forbids it
  /// (KERB_TOO_HIGH). What `render --color-by reason` and the page colour by.
  std::string deciding_reason;
  /// schema::judge_segment's verdict on the row (without the robot's rules).
  schema::Verdict verdict;
  /// The codes the build stored (the `reasons` column), in its order.
  std::vector<std::string> stored_reasons;
};

struct CrossingLayer {
  std::int64_t fid = 0;
  schema::PlanePoint point;
  bool designated = false;
  std::string crossing_type;
};

struct MapLayers {
  MapInfo info;
  UtmBox area;  ///< the area to show: the bbox, else the extent of all segments
  std::vector<SegmentLayer> segments;    ///< those meeting `area`, by fid
  std::vector<CrossingLayer> crossings;  ///< those inside `area`, by fid
  bool has_terrain = false;              ///< the DB holds the `terrain` gridded coverage
};

/// Name of the terrain gridded coverage written by roadcross-build --elevation.
inline constexpr const char* kTerrainTable = "terrain";

/// Opens the DB with the runtime and reads the layers inside `bbox` (all when unset). Throws
/// when the DB cannot be opened, lacks the segments or crossings table, or the bbox misses it.
MapLayers load_layers(const std::string& db_path, const std::optional<LonLatBox>& bbox);

/// The bbox in the map's UTM zone (the box around its four projected corners), checked to
/// overlap the map's extent; throws naming both when it does not.
UtmBox bbox_in_map(const LonLatBox& bbox, const MapInfo& info);

}  // namespace roadcross::viz
