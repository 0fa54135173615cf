// The road graph in the DB's UTM zone and its short segments, with every cost term the later
// stages fill in. A piece is the stretch of one way between two graph nodes (way ends and
// nodes shared by ways); pieces are cut into segments of at most max_segment_length_m.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/maybe.hpp"
#include "roadcross/preprocess/reasons.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

struct RoadNetwork;

/// A text interned in a TextPool (below), or none: 8 bytes where a std::string_view takes 16.
/// Reads as a std::string_view (empty for none); stays valid for the pool's lifetime.
class InternedText {
 public:
  InternedText() noexcept = default;
  explicit InternedText(const std::string* interned) noexcept : text_(interned) {}

  std::string_view view() const noexcept {
    return text_ ? std::string_view(*text_) : std::string_view();
  }
  operator std::string_view() const noexcept { return view(); }
  bool empty() const noexcept { return view().empty(); }
  friend bool operator==(InternedText a, std::string_view b) noexcept { return a.view() == b; }

 private:
  const std::string* text_ = nullptr;
};

enum class Landform : std::uint8_t;  // terrain.hpp

/// A segment's landform column in 1 byte (a name pointer takes 8): none (no elevation data),
/// one of the ten Landform classes of terrain.hpp, or the structure the segment is on.
class LandformLabel {
 public:
  LandformLabel() noexcept = default;
  explicit LandformLabel(Landform landform) noexcept;
  /// "tunnel" or "bridge".
  static LandformLabel structure(bool tunnel) noexcept;
  /// The text written to the DB (a static NUL-terminated name), or nullptr for none.
  const char* text() const noexcept;

 private:
  /// 0: none; 1..10: the Landform class + 1; then the structures.
  static constexpr std::uint8_t kNone = 0, kTunnel = 11, kBridge = 12;
  std::uint8_t code_ = kNone;
};

/// One short road segment and every cost term the stages fill in. Kept compact (terms as
/// Maybe<> numbers, reasons as a bit set, texts interned in the graph, fields ordered by size so
/// that there is no padding, the line's points in RoadGraph::segment_points; 272 bytes before,
/// 168 now): a country has tens of millions.
struct Segment {
  /// 1-based, stable for identical inputs: the segment's index in RoadGraph::segments + 1.
  std::int64_t id = 0;
  std::int64_t osm_way_id = 0;
  std::int64_t from_node_id = 0;  ///< OSM node id, or negative for a split point inside a way
  std::int64_t to_node_id = 0;
  double length_m = 0.0;
  InternedText highway;  ///< highway=* value, interned in RoadGraph::text
  InternedText name;     ///< the way's name, interned in RoadGraph::text (empty: none)
  const std::string* context_defaulted = nullptr;  ///< interned in RoadGraph::text, or none
  const std::string* override_note = nullptr;      ///< interned in RoadGraph::text, or none
  std::uint32_t piece_index = 0;  ///< index into RoadGraph::pieces (the way: its way_index)
  /// The line: RoadGraph::segment_points[first_point, first_point + point_count), UTM metres,
  /// >= 2 points (RoadGraph::line() gives it as a span).
  std::uint32_t first_point = 0;

  // Geometry cost.
  MaybeFloat junction_distance_m;
  MaybeFloat radius_m;
  // Terrain.
  MaybeFloat elevation_m, slope_deg, grade_percent, tpi_small_m, tpi_large_m;
  // Context.
  MaybeFloat maxspeed_kmh;
  MaybeInt lanes;
  MaybeFloat width_m;
  MaybeInt context_score;  ///< an int: operator overrides add to it without bound
  MaybeFloat crossing_distance_m;
  // Sight distance (forward / backward: looking along / against the way's direction).
  MaybeFloat sight_forward_m, sight_backward_m, sight_min_m, required_sight_m;
  ReasonSet reasons;

  std::uint16_t point_count = 0;
  // The 1-byte fields last (no padding between them and the 4-byte ones).
  MaybeSmallInt class_cost;       ///< geometry: 0..10 (the class cost parameters' range)
  MaybeSmallInt curvature_level;  ///< geometry: 0..5
  MaybeSmallInt curvature_cost;   ///< geometry: 0..14 (clamped)
  MaybeSmallInt elevation_cost;   ///< terrain: 0..9 (clamped)
  MaybeSmallInt rank;             ///< result: 0..14 (clamped)
  MaybeSmallInt score;            ///< result: 15 - rank
  LandformLabel landform;         ///< terrain: the landform class or structure, or none
  bool oneway : 1 = false;
  bool tunnel : 1 = false;
  bool bridge : 1 = false;
  bool override_no_crossing : 1 = false;     ///< an operator override forbids crossing here
  bool override_force_suitable : 1 = false;  ///< an operator override declares it suitable
};

/// Texts shared by many segments (way names, notes), stored once. Views and pointers into it
/// stay valid for the pool's lifetime (node-based storage).
class TextPool {
 public:
  const std::string* intern(std::string_view text) { return &*texts_.emplace(text).first; }
  InternedText intern_text(std::string_view text) { return InternedText(intern(text)); }

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
  /// The segments' lines, one after the other in segment order; consecutive segments of a piece
  /// share the point where one ends and the next starts.
  std::vector<PlanePoint> segment_points;
  std::uint64_t dropped_node_refs = 0;  ///< references to nodes missing from the file
  std::uint64_t dropped_ways = 0;       ///< ways with fewer than two located nodes

  /// Distance from the start of the segment's piece to the segment's start, metres: the
  /// segmenter cuts a piece into segment_count equal parts, so this is derived (exactly, the
  /// same arithmetic) from the segment's place in the piece rather than stored (8 bytes a
  /// segment).
  double offset_in_piece_m(const Segment& segment) const noexcept {
    const RoadPiece& piece = pieces[segment.piece_index];
    const auto k = static_cast<std::size_t>(segment.id - 1) - piece.first_segment;
    return piece.length_m / static_cast<double>(piece.segment_count) * static_cast<double>(k);
  }

  /// A segment's line (UTM metres, >= 2 points; what geometry functions take).
  std::span<const PlanePoint> line(const Segment& segment) const noexcept {
    return {segment_points.data() + segment.first_point, segment.point_count};
  }
};

/// One end of a road piece at a graph node.
struct Incidence {
  std::size_t piece = 0;  ///< index into RoadGraph::pieces
  bool at_end = false;    ///< the piece's to-node (else its from-node)
};
/// The piece ends at every graph node, by OSM node id, as one sorted table: 8 bytes a node and
/// 16 a piece end, where a hash map of vectors took ~130 bytes a node.
class Incidences {
 public:
  static constexpr std::size_t npos = static_cast<std::size_t>(-1);

  explicit Incidences(const RoadGraph& graph);
  /// The piece ends at `node` (OSM id) in piece order, a piece's from-end before its to-end;
  /// empty for a node that is not a graph node.
  std::span<const Incidence> at(std::int64_t node) const noexcept;
  /// Position of `node` among the graph nodes (sorted by id: 0 .. node_count() - 1), or npos.
  std::size_t index_of(std::int64_t node) const noexcept;
  std::size_t node_count() const noexcept { return nodes_.size(); }
  /// The piece ends at the node at position `index`.
  std::span<const Incidence> at_index(std::size_t index) const noexcept {
    return {ends_.data() + first_[index], ends_.data() + first_[index + 1]};
  }

 private:
  std::vector<std::int64_t> nodes_;  ///< graph node ids, sorted
  std::vector<std::size_t> first_;   ///< nodes_.size() + 1 offsets into ends_
  std::vector<Incidence> ends_;      ///< node by node
};
inline Incidences incidences_of(const RoadGraph& graph) {
  return Incidences(graph);
}

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
