// The road graph in the DB's UTM zone and its short segments, with every cost term the later
// stages fill in. A piece is the stretch of one way between two graph nodes (way ends and
// nodes shared by ways); pieces are cut into segments of at most max_segment_length_m.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/maybe.hpp"
#include "roadcross/preprocess/common/reasons.hpp"
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

/// One short road segment and every cost term the stages fill in. Kept compact: a country
/// has tens of millions (7.39 M at 200x Monaco, where each byte is 7 MiB of the peak). What the
/// segment's piece or its place in the graph determines is derived rather than stored, through
/// RoadGraph's accessors: its id (index + 1), its way's OSM id, highway, name, class cost,
/// speed limit, lanes and width (per piece), its end node ids, its length and its line's
/// point count (from its place in its piece), its score (from its rank); the two note texts
/// are one index into RoadGraph::notes. Terms are Maybe<> numbers, reasons a bit set, the
/// line's points in RoadGraph::segment_points; fields ordered by size, so that there is no
/// padding (4-byte alignment: nothing in it is 8 bytes). 272 bytes, then 160, now 72.
struct Segment {
  std::uint32_t piece_index = 0;  ///< index into RoadGraph::pieces (the way: its way_index)
  /// The line's first point in RoadGraph::segment_points (UTM metres; RoadGraph::line() gives
  /// the line, >= 2 points, as a span).
  std::uint32_t first_point = 0;

  // Geometry cost (the class cost is the way's: RoadPiece).
  MaybeFloat junction_distance_m;
  MaybeFloat radius_m;
  // Terrain.
  MaybeFloat elevation_m, slope_deg, grade_percent, tpi_small_m, tpi_large_m;
  // Context (the way's speed, lanes and width are its piece's: RoadPiece).
  MaybeInt context_score;  ///< an int: operator overrides add to it without bound
  MaybeFloat crossing_distance_m;
  // Sight distance (forward / backward: looking along / against the way's direction).
  MaybeFloat sight_forward_m, sight_backward_m, sight_min_m, required_sight_m;
  /// The context_defaulted and override_note texts: an index into RoadGraph::notes (0: none;
  /// read and set through RoadGraph::context_defaulted() / override_note()).
  std::uint32_t notes = 0;

  ReasonSet reasons;  ///< 2 bytes
  // The 1-byte fields last (no padding between them and the 2- and 4-byte ones).
  MaybeSmallInt curvature_level;  ///< geometry: 0..5
  MaybeSmallInt curvature_cost;   ///< geometry: 0..14 (clamped)
  MaybeSmallInt elevation_cost;   ///< terrain: 0..9 (clamped)
  MaybeSmallInt rank;             ///< result: 0..14 (clamped)
  LandformLabel landform;         ///< terrain: the landform class or structure, or none
  // The way's flags, repeated here (1 byte for the five) because the terrain and sight stages
  // read them with only the segment at hand.
  bool oneway : 1 = false;
  bool tunnel : 1 = false;
  bool bridge : 1 = false;
  bool override_no_crossing : 1 = false;     ///< an operator override forbids crossing here
  bool override_force_suitable : 1 = false;  ///< an operator override declares it suitable

  /// The result's score, 15 - rank (none before the ranks are computed).
  MaybeSmallInt score() const noexcept { return rank ? MaybeSmallInt(15 - *rank) : rank; }
};
// A regression guard: the segment table is most of the build's peak memory. 72 bytes, no
// padding: the piece and first-point indices (8), 12 float terms and the context score (52),
// the notes index (4), the reasons (2), four 1-byte costs, the landform and the flags (6).
static_assert(sizeof(Segment) == 72, "Segment changed size: every byte costs ~7 MiB at 200x");
static_assert(alignof(Segment) == 4, "an 8-byte field in Segment would pad it to 8-byte steps");

/// A segment's two note texts (interned in RoadGraph::text, or none).
struct SegmentNotes {
  const std::string* context_defaulted = nullptr;  ///< the context tags that took defaults
  const std::string* override_note = nullptr;      ///< the operator overrides' notes
  bool operator==(const SegmentNotes&) const = default;
};

/// The distinct (context_defaulted, override_note) pairs, each stored once: segments hold a
/// 4-byte index (two pointers took 16 bytes a segment, for a few dozen distinct pairs).
class NoteTable {
 public:
  NoteTable() : pairs_(1) {}  // index 0: no notes (a default Segment's)
  const SegmentNotes& at(std::uint32_t index) const noexcept { return pairs_[index]; }
  /// The index of `notes`, added if new. Throws std::length_error past 2^32 pairs.
  std::uint32_t index_of(const SegmentNotes& notes);
  std::size_t size() const noexcept { return pairs_.size(); }

 private:
  struct Hash {
    std::size_t operator()(const SegmentNotes& n) const noexcept {
      return std::hash<const void*>()(n.context_defaulted) * 31u ^
             std::hash<const void*>()(n.override_note);
    }
  };
  std::vector<SegmentNotes> pairs_;
  std::unordered_map<SegmentNotes, std::uint32_t, Hash> index_;
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
  // The way's columns, kept per piece (~1 piece for 13 segments) rather than per segment.
  std::int64_t osm_way_id = 0;
  InternedText highway;      ///< highway=* value, interned in RoadGraph::text
  InternedText name;         ///< the way's name, interned in RoadGraph::text (empty: none)
  MaybeSmallInt class_cost;  ///< 0..10: from the highway (set by the geometry stage)
  // The way's context (set by the context stage; read through RoadGraph for a segment).
  MaybeFloat maxspeed_kmh;  ///< km/h, tagged or the country's implicit limit
  MaybeInt lanes;
  MaybeFloat width_m;              ///< carriageway width, metres
  std::vector<PlanePoint> points;  ///< the OSM vertices of the piece, UTM metres
  /// OSM node id of each vertex in `points`: for the crossings search of the context stage,
  /// emptied after it (RoadGraph::free_piece_node_ids).
  std::vector<std::int64_t> node_ids;
  double length_m = 0.0;
  std::size_t first_segment = 0;  ///< index into the segment vector
  std::size_t segment_count = 0;
};

struct RoadGraph {
  geo::UtmZone zone;
  TextPool text;  ///< names and notes the pieces and `notes` point into
  std::vector<RoadPiece> pieces;
  /// Number of piece ends at each graph node (a way passing through counts 2, ending counts 1).
  std::unordered_map<std::int64_t, int> degree;
  std::vector<Segment> segments;
  /// The segments' lines, one after the other in segment order; consecutive segments of a piece
  /// share the point where one ends and the next starts.
  std::vector<PlanePoint> segment_points;
  std::uint64_t dropped_node_refs = 0;  ///< references to nodes missing from the file
  std::uint64_t dropped_ways = 0;       ///< ways with fewer than two located nodes

  NoteTable notes;  ///< the segments' note pairs (Segment::notes indexes it)

  // What a segment's piece and its place in `segments` determine, derived rather than stored.
  // `segment` must be an element of `segments` (its index is its address's offset).

  /// The segment's index in `segments`.
  std::size_t index_of(const Segment& segment) const noexcept {
    return static_cast<std::size_t>(&segment - segments.data());
  }
  /// The segment's id in the DB: 1-based, stable for identical inputs (index + 1).
  static std::int64_t id_at(std::size_t index) noexcept {
    return static_cast<std::int64_t>(index) + 1;
  }
  std::int64_t id_of(const Segment& segment) const noexcept { return id_at(index_of(segment)); }

  /// The segment's place in its piece: 0 .. segment_count - 1.
  std::size_t place_in_piece(const Segment& segment) const noexcept {
    return index_of(segment) - pieces[segment.piece_index].first_segment;
  }

  /// Distance from the start of the segment's piece to the segment's start, metres: the
  /// segmenter cuts a piece into segment_count equal parts, so this is derived (exactly, the
  /// same arithmetic as build_road_graph's) from the segment's place in the piece.
  double offset_in_piece_m(const Segment& segment) const noexcept {
    const RoadPiece& piece = pieces[segment.piece_index];
    return part_length_m(piece) * static_cast<double>(place_in_piece(segment));
  }
  /// The segment's length, metres (the same arithmetic as build_road_graph's: the last part
  /// ends at the piece's length, so the lengths of a piece add up to it).
  double length_m(const Segment& segment) const noexcept {
    const RoadPiece& piece = pieces[segment.piece_index];
    const std::size_t k = place_in_piece(segment);
    const double start_m = part_length_m(piece) * static_cast<double>(k);
    const double end_m = k + 1 == piece.segment_count
                             ? piece.length_m
                             : part_length_m(piece) * static_cast<double>(k + 1);
    return end_m - start_m;
  }

  /// OSM node id at the segment's start: its piece's from-node for the first segment of a
  /// piece, else the split point the previous segment ends at (see to_node_id).
  std::int64_t from_node_id(const Segment& segment) const noexcept {
    const std::size_t index = index_of(segment);
    const RoadPiece& piece = pieces[segment.piece_index];
    return index == piece.first_segment ? piece.from_node_id : split_node_id(index - 1);
  }
  /// OSM node id at the segment's end: its piece's to-node for the last segment of a piece,
  /// else the (negative) id of the split point between it and the next segment.
  std::int64_t to_node_id(const Segment& segment) const noexcept {
    const std::size_t index = index_of(segment);
    const RoadPiece& piece = pieces[segment.piece_index];
    return index + 1 == piece.first_segment + piece.segment_count ? piece.to_node_id
                                                                  : split_node_id(index);
  }
  /// The id of the split point at the end of the segment at `index` (not the last of its
  /// piece): split points are numbered -1, -2, ... in segment order, one after every segment
  /// but each piece's last, so before it come `index` segments, of which `piece_index` are
  /// the last of theirs: -(index - piece_index) - 1.
  std::int64_t split_node_id(std::size_t index) const noexcept {
    return static_cast<std::int64_t>(segments[index].piece_index) -
           static_cast<std::int64_t>(index) - 1;
  }

  // The way's columns, from the segment's piece.
  std::int64_t osm_way_id(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].osm_way_id;
  }
  InternedText highway(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].highway;
  }
  InternedText name(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].name;
  }
  /// The way's class cost (set by the geometry stage).
  MaybeSmallInt class_cost(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].class_cost;
  }

  // The way's context, from the segment's piece.
  MaybeFloat maxspeed_kmh(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].maxspeed_kmh;
  }
  MaybeInt lanes(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].lanes;
  }
  MaybeFloat width_m(const Segment& segment) const noexcept {
    return pieces[segment.piece_index].width_m;
  }

  // The segment's notes (interned in `text`, or nullptr for none).
  const std::string* context_defaulted(const Segment& segment) const noexcept {
    return notes.at(segment.notes).context_defaulted;
  }
  const std::string* override_note(const Segment& segment) const noexcept {
    return notes.at(segment.notes).override_note;
  }
  void set_context_defaulted(Segment& segment, const std::string* interned) {
    SegmentNotes n = notes.at(segment.notes);
    n.context_defaulted = interned;
    segment.notes = notes.index_of(n);
  }
  void set_override_note(Segment& segment, const std::string* interned) {
    SegmentNotes n = notes.at(segment.notes);
    n.override_note = interned;
    segment.notes = notes.index_of(n);
  }

  /// Frees every piece's node_ids (the crossings search, in the context stage, is their last
  /// reader): 8 bytes a piece vertex and a heap block a piece through the later stages.
  void free_piece_node_ids() noexcept {
    for (RoadPiece& piece : pieces) std::vector<std::int64_t>().swap(piece.node_ids);
  }

  /// A segment's line (UTM metres, >= 2 points; what geometry functions take). It ends where
  /// the next segment's starts: on that point itself within a piece (shared), just before it
  /// at a piece's end (a piece's first segment starts on a point of its own), at the end of
  /// segment_points for the last segment.
  std::span<const PlanePoint> line(const Segment& segment) const noexcept {
    const std::size_t next = index_of(segment) + 1;
    std::size_t end = segment_points.size();
    if (next < segments.size()) {
      end = segments[next].first_point;
      if (segments[next].piece_index == segment.piece_index) ++end;
    }
    return {segment_points.data() + segment.first_point, end - segment.first_point};
  }

 private:
  /// The length of each of a piece's equal segments, metres.
  static double part_length_m(const RoadPiece& piece) noexcept {
    return piece.length_m / static_cast<double>(piece.segment_count);
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

/// The UTM bounding box of every road point (metres; empty: +inf mins, -inf maxes). Computed
/// once per build, after segmenting, for the stages that work over the roads' area.
struct RoadBounds {
  double min_e = std::numeric_limits<double>::infinity();
  double min_n = std::numeric_limits<double>::infinity();
  double max_e = -std::numeric_limits<double>::infinity();
  double max_n = -std::numeric_limits<double>::infinity();
};
RoadBounds road_bounds(const RoadGraph& graph);

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
