// The road graph in the DB's UTM zone and its short segments, with every cost term the later
// stages fill in. A piece is the stretch of one way between two graph nodes (way ends and
// nodes shared by ways); pieces are cut into segments of at most max_segment_length_m.
#pragma once

#include <boost/container/small_vector.hpp>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/maybe.hpp"
#include "roadcross/preprocess/reasons.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

struct RoadNetwork;

/// A segment's line: almost always 2 points (a straight 10 m cut), kept inline.
using SegmentPoints = boost::container::small_vector<PlanePoint, 2>;

/// One short road segment and every cost term the stages fill in. Kept compact (terms as
/// Maybe<> numbers, reasons as a bit set, texts interned in the graph): a country has tens of
/// millions of them.
struct Segment {
  std::int64_t id = 0;             ///< 1-based, stable for identical inputs
  std::uint32_t way_index = 0;     ///< index into RoadNetwork::ways
  std::uint32_t piece_index = 0;   ///< index into RoadGraph::pieces
  double offset_in_piece_m = 0.0;  ///< distance from the piece's start to this segment's start
  std::int64_t osm_way_id = 0;
  std::string_view highway;       ///< highway=* value, interned in RoadGraph::text
  std::string_view name;          ///< the way's name, interned in RoadGraph::text (empty: none)
  std::int64_t from_node_id = 0;  ///< OSM node id, or negative for a split point inside a way
  std::int64_t to_node_id = 0;
  SegmentPoints points;  ///< UTM metres, >= 2 points
  double length_m = 0.0;
  bool oneway = false;
  bool tunnel = false;
  bool bridge = false;
  bool override_no_crossing = false;     ///< an operator override forbids crossing here
  bool override_force_suitable = false;  ///< an operator override declares it suitable

  // Geometry cost.
  MaybeInt class_cost;
  MaybeFloat junction_distance_m;
  MaybeFloat radius_m;
  MaybeInt curvature_level;
  MaybeInt curvature_cost;
  // Terrain.
  MaybeFloat elevation_m, slope_deg, grade_percent, tpi_small_m, tpi_large_m;
  const char* landform = nullptr;  ///< a static class name ("plains", "bridge", ...) or none
  MaybeInt elevation_cost;
  // Context.
  MaybeFloat maxspeed_kmh;
  MaybeInt lanes;
  MaybeFloat width_m;
  MaybeInt context_score;
  MaybeFloat crossing_distance_m;
  const std::string* context_defaulted = nullptr;  ///< interned in RoadGraph::text, or none
  const std::string* override_note = nullptr;      ///< interned in RoadGraph::text, or none
  // Sight distance (forward / backward: looking along / against the way's direction).
  MaybeFloat sight_forward_m, sight_backward_m, sight_min_m, required_sight_m;
  // Result.
  MaybeInt rank, score;
  ReasonSet reasons;

  /// The points as a span (what geometry functions take).
  std::span<const PlanePoint> line() const noexcept { return {points.data(), points.size()}; }
};

/// Texts shared by many segments (way names, notes), stored once. Views and pointers into it
/// stay valid for the pool's lifetime (node-based storage).
class TextPool {
 public:
  const std::string* intern(std::string_view text) { return &*texts_.emplace(text).first; }

 private:
  std::unordered_set<std::string> texts_;
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
  TextPool text;  ///< names and notes the segments point into
  std::vector<RoadPiece> pieces;
  /// Number of piece ends at each graph node (a way passing through counts 2, ending counts 1).
  std::unordered_map<std::int64_t, int> degree;
  std::vector<Segment> segments;
  std::uint64_t dropped_node_refs = 0;  ///< references to nodes missing from the file
  std::uint64_t dropped_ways = 0;       ///< ways with fewer than two located nodes
};

/// One end of a road piece at a graph node.
struct Incidence {
  std::size_t piece = 0;  ///< index into RoadGraph::pieces
  bool at_end = false;    ///< the piece's to-node (else its from-node)
};
/// The piece ends at every graph node, by OSM node id.
using Incidences = std::unordered_map<std::int64_t, std::vector<Incidence>>;
Incidences incidences_of(const RoadGraph& graph);

/// UTM zone of the centre of the bounding box of the located road nodes.
geo::UtmZone choose_utm_zone(const RoadNetwork& network);

/// Splits ways at graph nodes (way ends and nodes used more than once, matched on OSM node id)
/// and cuts each piece into equal segments of at most `max_segment_length_m` (metres, > 0).
/// References to nodes missing from the file split the way there (counted, not fatal).
RoadGraph build_road_graph(const RoadNetwork& network, geo::UtmZone zone,
                           double max_segment_length_m);

/// Number of equal segments a piece of `piece_length_m` (metres, >= 0) is cut into: the fewest
/// of at most `max_segment_length_m` (metres, > 0), at least 1; a piece longer than the limit
/// by less than a nanometre per limit (rounding) is not cut once more.
std::size_t segment_count_of(double piece_length_m, double max_segment_length_m) noexcept;

/// Length of a polyline, metres.
double polyline_length_m(std::span<const PlanePoint> points) noexcept;

}  // namespace roadcross::preprocess
