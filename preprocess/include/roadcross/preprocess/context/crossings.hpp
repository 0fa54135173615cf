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

#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess {

struct CrossingKind {
  /// crossing=* value (zebra, marked, uncontrolled, traffic_signals, unmarked, informal, no,
  /// ...), else the crossing_ref (zebra, pelican, toucan, ...), else "marked"/"unmarked" from
  /// crossing:markings, else "traffic_signals" from crossing:signals=yes, else "unspecified".
  std::string type;
  bool signals = false;    ///< controlled by traffic lights
  bool designated = true;  ///< false for crossing=informal and crossing=no: no bonus
};

/// Kind of a node's crossing, or nullopt when its tags do not mark one.
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
};

/// Every crossing of the network on the graph, ordered by (osm_type, osm_id, position along
/// the crossing way). A crossing way that meets a road at a crossing node adds no second row.
std::vector<Crossing> find_crossings(const RoadNetwork& network, const RoadGraph& graph);

/// Sets crossing_distance_m of every segment: the graph distance from its midpoint along the
/// road to the nearest designated crossing; left empty when its connected road has none.
void assign_crossing_distances(RoadGraph& graph, const std::vector<Crossing>& crossings);

}  // namespace roadcross::preprocess
