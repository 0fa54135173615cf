// Designated crossings: crossing nodes on road ways (highway=crossing, crossing=*,
// crossing:markings, crossing:signals, crossing_ref) and the places where footway=crossing /
// cycleway=crossing ways meet a road (a shared node, or a geometric intersection when the
// mapper did not join them). Each is located on the road graph by node identity, so that
// distances along the road are graph distances, not straight lines.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::preprocess {

struct CrossingKind {
  /// crossing=* value (zebra, marked, uncontrolled, traffic_signals, unmarked, informal, no,
  /// ...), else the crossing_ref (zebra, pelican, toucan, ...), else "marked"/"unmarked" from
  /// crossing:markings, else "traffic_signals" from crossing:signals=yes, else "unspecified".
  std::string type;
  bool signals = false;    ///< controlled by traffic lights
  bool designated = true;  ///< false for crossing=informal and crossing=no: no bonus
};

/// Kind of a node's crossing, or nullopt when its tags do not mark one. tactile_paving=yes
/// (or contrasted, primitive, incorrect) on a node of a road marks a designated crossing: the
/// paving is laid where pedestrians are meant to cross.
std::optional<CrossingKind> node_crossing_kind(const Tags& tags);

/// Kind of a footway=crossing / cycleway=crossing way from its tags.
CrossingKind way_crossing_kind(const Tags& tags);

struct Crossing {
  std::int64_t osm_id = 0;
  std::string osm_type;  ///< "node" or "way"
  CrossingKind kind;
  PlanePoint point;             ///< UTM metres
  std::int64_t segment_id = 0;  ///< the segment the crossing lies on
  std::size_t piece_index = 0;  ///< where it lies on the road graph
  double offset_in_piece_m = 0.0;
  /// Kerbs and refuge island: the crossing node's tags, merged with those of the crossing
  /// ways through it and of their kerb nodes (for a crossing way: its tags and its nodes').
  KerbFacts kerb;
};

/// Every crossing of the network on the graph, ordered by (osm_type, osm_id, position along
/// the crossing way). A crossing way that meets a road at a crossing node adds no second row.
std::vector<Crossing> find_crossings(const RoadNetwork& network, const RoadGraph& graph);

/// Kerb and island facts at places on the road graph: every crossing's, and every road node's
/// that carries kerb tags without being a crossing (barrier=kerb where a footway meets the
/// carriageway). Stored in graph.kerbs for the segment holding each place and for the
/// segments of the same piece whose midpoint lies within `reach_m` of it along the road (the
/// reach of the crossing bonus); where several places reach a segment, the facts merge.
void assign_kerbs(RoadGraph& graph, const RoadNetwork& network,
                  const std::vector<Crossing>& crossings, double reach_m);

/// Sets each piece's sidewalks from its way's tags (sidewalk_sides) and, on a side the tags
/// leave unknown, from separately mapped footway=sidewalk ways: the side has a pavement when
/// at least half of the piece's segment midpoints have a sidewalk edge within
/// width / 2 + `sidewalk_reach_m` on that side, running within 30 degrees of the road.
void assign_sidewalks(RoadGraph& graph, const RoadNetwork& network, double sidewalk_reach_m);

/// Sets crossing_distance_m of every segment: the graph distance from its midpoint along the
/// road to the nearest designated crossing; left empty when its connected road has none.
void assign_crossing_distances(RoadGraph& graph, const std::vector<Crossing>& crossings);

}  // namespace roadcross::preprocess
