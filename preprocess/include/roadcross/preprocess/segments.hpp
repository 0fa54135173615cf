// The road graph in the DB's UTM zone and its short segments, with every cost term the later
// stages fill in. A piece is the stretch of one way between two graph nodes (way ends and
// nodes shared by ways); pieces are cut into segments of at most max_segment_length_m.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

struct RoadNetwork;

struct Segment {
  std::int64_t id = 0;             ///< 1-based, stable for identical inputs
  std::size_t way_index = 0;       ///< index into RoadNetwork::ways
  std::size_t piece_index = 0;     ///< index into RoadGraph::pieces
  double offset_in_piece_m = 0.0;  ///< distance from the piece's start to this segment's start
  std::int64_t osm_way_id = 0;
  std::string highway;
  std::string name;
  std::int64_t from_node_id = 0;  ///< OSM node id, or negative for a split point inside a way
  std::int64_t to_node_id = 0;
  std::vector<PlanePoint> points;  ///< UTM metres, >= 2 points
  double length_m = 0.0;
  bool oneway = false;
  bool tunnel = false;
  bool bridge = false;

  // Geometry cost.
  std::optional<int> class_cost;
  std::optional<double> junction_distance_m;
  std::optional<double> radius_m;
  std::optional<int> curvature_level;
  std::optional<int> curvature_cost;
  // Terrain.
  std::optional<double> elevation_m, slope_deg, grade_percent, tpi_small_m, tpi_large_m;
  std::optional<std::string> landform;
  std::optional<int> elevation_cost;
  // Context.
  std::optional<double> maxspeed_kmh;
  std::optional<int> lanes;
  std::optional<double> width_m;
  std::optional<int> context_score;
  std::optional<double> crossing_distance_m;
  std::optional<std::string> context_defaulted;
  std::optional<std::string> override_note;
  bool override_no_crossing = false;     ///< an operator override forbids crossing here
  bool override_force_suitable = false;  ///< an operator override declares it suitable
  // Result.
  std::optional<int> rank, score;
  std::vector<std::string> reasons;
};

struct RoadPiece {
  std::size_t way_index = 0;
  std::int64_t from_node_id = 0;  ///< OSM id of the graph node at the start
  std::int64_t to_node_id = 0;
  std::vector<PlanePoint> points;      ///< the OSM vertices of the piece, UTM metres
  std::vector<std::int64_t> node_ids;  ///< OSM node id of each vertex in `points`
  double length_m = 0.0;
  std::size_t first_segment = 0;  ///< index into the segment vector
  std::size_t segment_count = 0;
};

struct RoadGraph {
  geo::UtmZone zone;
  std::vector<RoadPiece> pieces;
  /// Number of piece ends at each graph node (a way passing through counts 2, ending counts 1).
  std::unordered_map<std::int64_t, int> degree;
  std::vector<Segment> segments;
  std::uint64_t dropped_node_refs = 0;  ///< references to nodes missing from the file
  std::uint64_t dropped_ways = 0;       ///< ways with fewer than two located nodes
};

/// UTM zone of the centre of the bounding box of the located road nodes.
geo::UtmZone choose_utm_zone(const RoadNetwork& network);

/// Splits ways at graph nodes (way ends and nodes used more than once, matched on OSM node id)
/// and cuts each piece into equal segments of at most `max_segment_length_m` (metres, > 0).
/// References to nodes missing from the file split the way there (counted, not fatal).
RoadGraph build_road_graph(const RoadNetwork& network, geo::UtmZone zone,
                           double max_segment_length_m);

/// Length of a polyline, metres.
double polyline_length_m(const std::vector<PlanePoint>& points) noexcept;

}  // namespace roadcross::preprocess
