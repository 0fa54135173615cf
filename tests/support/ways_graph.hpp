// A road graph from hand-written ways, for the sight tests: points are UTM offsets in metres,
// so that expected distances can be worked out by hand.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::testing {

/// A graph of residential ways through points given as offsets (metres) from (east_m, north_m)
/// in `zone`; equal points are one node (where ways meet). Cut into segments of at most
/// `segment_m`.
inline preprocess::RoadGraph graph_of_ways(const std::vector<std::vector<schema::PlanePoint>>& ways,
                                           double segment_m, const geo::UtmZone& zone,
                                           double east_m, double north_m) {
  preprocess::RoadNetwork network;
  std::vector<schema::PlanePoint> nodes;
  const auto node_id = [&](const schema::PlanePoint& q) {
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      if (nodes[i].x == q.x && nodes[i].y == q.y) return static_cast<std::int64_t>(i + 1);
    }
    nodes.push_back(q);
    const geo::LatLon ll = geo::utm_to_wgs84(east_m + q.x, north_m + q.y, zone);
    const auto id = static_cast<std::int64_t>(nodes.size());
    network.locations.push_back({id, ll.lat_deg, ll.lon_deg});
    return id;
  };
  for (std::size_t w = 0; w < ways.size(); ++w) {
    preprocess::RoadWay way;
    way.osm_id = static_cast<std::int64_t>(w + 1);
    way.highway = "residential";
    way.tags = {{"highway", "residential"}};
    for (const schema::PlanePoint& q : ways[w]) way.node_ids.push_back(node_id(q));
    network.ways.push_back(way);
  }
  return preprocess::build_road_graph(network, zone, segment_m);
}

}  // namespace roadcross::testing
