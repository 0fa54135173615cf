// Sight distance: how far along the road a robot standing at the kerb of a segment
// sees an approaching vehicle, in both directions, with the line of sight blocked by the
// terrain, by buildings (opaque prisms) and by walls and fences; and the sight distance a
// crossing needs at the road's speed. Fills sight_forward_m, sight_backward_m, sight_min_m,
// required_sight_m and the reason LIMITED_VISIBILITY. docs/cost-model.md "Sight distance"
// explains the method, its rule for following the road through junctions and what it ignores.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/done_prefix.hpp"
#include "roadcross/preprocess/common/id_buckets.hpp"
#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/sight/obstacle_edge.hpp"
#include "roadcross/preprocess/terrain/terrain_grid.hpp"

namespace roadcross::preprocess {

class Progress;

struct SightParameters {
  double enabled = 1.0;             ///< 0: the stage is skipped (sight columns NULL)
  double sensor_height_m = 0.6;     ///< robot's sensor above the ground at the kerb
  double object_height_m = 1.1;     ///< lowest part of a vehicle that must be seen
  double range_m = 300.0;           ///< sight is not looked for beyond this, along the road
  double step_m = 5.0;              ///< vehicle positions tried along the road (then bisected)
  double default_width_m = 6.0;     ///< carriageway width when the context gives none
  double default_speed_kmh = 50.0;  ///< road speed when the context gives none
  double crossing_speed_mps = 1.0;  ///< robot's speed while crossing
  double startup_time_s = 1.0;      ///< from the decision to moving
  double margin_s = 1.0;            ///< safety margin on top of the crossing time
  double building_height_m = 8.0;   ///< building without height or building:levels
  double level_height_m = 3.0;      ///< height of one building:levels level
  double wall_height_m = 2.0;       ///< barrier=wall without height
  double fence_height_m = 1.5;      ///< barrier=fence without height
  /// 1: LIMITED_VISIBILITY makes a segment unsuitable (applied by the runtime); 0: it only
  /// adds rank_penalty to the rank.
  double limited_visibility_unsuitable = 1.0;
  double rank_penalty = 4.0;

  void describe(std::vector<ParameterSpec>& out);
};

struct ObstacleReport {
  std::size_t buildings = 0, walls = 0, fences = 0;
  std::size_t default_height = 0;  ///< obstacles that took a default height
  std::size_t edges = 0;
  std::size_t relations_skipped = 0;  ///< multipolygon buildings (not read, see the docs)
};

struct Obstacles {
  ObstacleEdges edges;  ///< runs in the order of their ways in the file
  ObstacleReport report;
};

/// A height tag ("12", "12.5 m", "12m", "40 ft", "40'") in metres; NaN when unreadable.
double parse_height_m(std::string_view text) noexcept;

/// The values of the keys an obstacle way is read by (nullptr when absent; the first when a key
/// is repeated, as osmium's TagList::operator[] gives), found in one walk over the tag list.
struct ObstacleTags {
  const char* building = nullptr;
  const char* barrier = nullptr;
  const char* height = nullptr;
  const char* building_levels = nullptr;  ///< building:levels
  const char* min_height = nullptr;
  const char* building_min_level = nullptr;  ///< building:min_level
};
ObstacleTags read_obstacle_tags(const osmium::TagList& tags) noexcept;

/// Reads building footprints (closed ways with building=*, except roof and no) and
/// barrier=wall/fence ways in the road network's two passes: give it to read_road_network().
/// The way pass keeps per obstacle way 12 bytes and per node reference 8 (its id). Then every
/// reference gets the slot it will have among the edges (ObstacleEdges' layout: a header slot
/// before each way), filled in the node pass with the node's location (its first reference) or
/// the slot of its first reference (the others: a node shared by two buildings, a ring's last
/// node); the look-up is by id in a sorted table of 12 bytes a reference, freed after the pass.
/// A slot is 8 bytes throughout: until take_edges() it holds a Location's two int32; take_edges()
/// projects each node once to a fixed-point vertex in the same slot (VertexFrame) and compacts
/// the runs in place: the edges never exist twice, nor as 40-byte edges.
class ObstacleReader final : public ExtraOsmReader {
 public:
  explicit ObstacleReader(const SightParameters& parameters) : p_(parameters) {}
  void way(const osmium::Way& way) override;
  void relation(const osmium::Relation& relation) override;
  bool wants_relations() const override { return true; }
  void ways_done() override;
  void node(std::int64_t id, osmium::Location location) override;
  void nodes_done() override;

  /// The edges that come within `reach_m` of the box [min, max] (UTM, zone `zone`); nodes more
  /// than 1 km beyond that are dropped with their edges. Each way's chains of such edges become
  /// runs, in the ways' order in the file. Frees what was read.
  Obstacles take_edges(const geo::UtmZone& zone, const PlanePoint& min, const PlanePoint& max,
                       double reach_m);

 private:
  struct Way {
    std::uint32_t first_slot = 0;  ///< its header slot; its vertices follow
    float bottom_m = 0.0f, top_m = 0.0f;
  };
  /// A node reference's slot, by node id (12 bytes, not 16). No default member initialisers:
  /// a table of them is allocated without writing its pages (they are all placed).
  struct NodeSlot {
    std::uint32_t id_low, id_high, slot;
    std::int64_t id() const {
      return static_cast<std::int64_t>((std::uint64_t{id_high} << 32) | id_low);
    }
  };
  /// Slots of ways_[w]'s vertices: [first_slot + 1, end_slot(w)).
  std::size_t end_slot(std::size_t w) const {
    return w + 1 < ways_.size() ? ways_[w + 1].first_slot : slots_.size();
  }
  const SightParameters& p_;
  ObstacleReport report_;
  std::vector<Way> ways_;
  std::size_t cut_slots_ = 0;       ///< slots the cuts of long chains add (before the ways')
  std::vector<std::int64_t> refs_;  ///< node ids of ways_ (first pass only)
  std::vector<NodeSlot, UninitialisedAllocator<NodeSlot>> node_slots_;  ///< by id; node pass
  /// node_slots_' index: a node's look-up searches one bucket (at most 2^20 of them, 4 MB).
  IdBuckets buckets_;
  /// cut_slots_ free slots, then per way a header slot and per reference a Location's (x, y);
  /// or (kReference, the slot of the node's first reference); or kNoVertex twice when the node
  /// is not in the file (obstacles.cpp). take_edges() turns them into ObstacleEdges' slots.
  ObstacleEdges::Slots slots_;
};

struct SightReport {
  std::size_t segments = 0;         ///< segments with a sight distance
  std::size_t limited = 0;          ///< of them LIMITED_VISIBILITY
  std::size_t skipped_tunnels = 0;  ///< tunnel segments (no sight computed)
  /// Lines of sight tested one by one (vehicle positions and the bisection), each against its
  /// fan's candidate edges (and the terrain); with a terrain only (flat ground reads shadows).
  std::size_t lines_of_sight = 0;
  /// Fans of consecutive positions tried; on flat ground the chunks (one hull for both kerbs).
  std::size_t fans = 0;
  std::size_t clear_fans = 0;       ///< of them without a candidate edge
  std::size_t fan_positions = 0;    ///< positions clear fans settled without a line (no terrain)
  std::size_t candidate_edges = 0;  ///< the fans' candidate edges (that may block a line)
  /// Road directions tried as open to both kerbs at once (no obstacle near any of their lines;
  /// without a terrain only), and of them found open: no search, the answer is the range.
  std::size_t open_directions_tried = 0;
  std::size_t open_directions = 0;
};

/// Fills the sight fields of every segment (run after terrain and context). `terrain` is the
/// elevation grid (nullptr: flat ground); road surface elevations are taken from it, and from
/// elevation_m at the robot's own segment (bridges). Uses every core. The answers do not depend
/// on the order of the edges; their order in memory only makes it faster (see
/// ObstacleReader::take_edges). `done` (optional, of graph.segments.size() items) is told which
/// segments are final as the threads finish them, so that they can be written meanwhile; the
/// segments are taken in chunks in index order, so they become final roughly as a growing prefix.
/// A stop of `done`'s consumer ends the stage with DonePrefix::Stopped.
SightReport compute_sight(RoadGraph& graph, const Grid* terrain, const ObstacleEdges& obstacles,
                          const SightParameters& parameters, DonePrefix* done = nullptr);

/// In cost mode (limited_visibility_unsuitable = 0), adds rank_penalty to the rank of every
/// LIMITED_VISIBILITY segment (clamped to 14) and recomputes its score; run after the ranks.
void apply_sight_rank_penalty(RoadGraph& graph, const SightParameters& parameters);
/// The same for one segment (after its rank and its sight).
void apply_sight_rank_penalty(Segment& segment, const SightParameters& parameters);

}  // namespace roadcross::preprocess
