// Geometry cost end to end from OSM XML: reading, node identity, projection, segmentation and the
// geometry stage together. Node positions are chosen in UTM zone 33N metres (around E 460 000,
// N 5 540 000) and converted to WGS84 with GeographicLib, so lengths and radii are known by
// construction; OSM stores 1e-7 degrees (about 1 cm), which bounds the tolerances below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "osm_fixture.hpp"
#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/geometry/geometry_cost.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/rank.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
namespace geo = roadcross::geo;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr geo::UtmZone kZone{33, true};
constexpr double kOriginEast_m = 460000.0, kOriginNorth_m = 5540000.0;

/// An OSM node at (east_m, north_m) metres from the test origin in UTM 33N.
std::string node_at(long id, double east_m, double north_m) {
  const geo::LatLon p = geo::utm_to_wgs84(kOriginEast_m + east_m, kOriginNorth_m + north_m, kZone);
  return rt::osm_node(id, p.lat_deg, p.lon_deg);
}

/// Reads `body` as an OSM file and runs segmentation (10 m), the geometry stage and the rank.
rp::RoadGraph build(const std::string& body) {
  rt::TempDir dir;
  const std::string path = dir.write("test.osm", rt::osm_document(body));
  rp::Progress quiet(false);
  const rp::RoadNetwork network = rp::read_road_network(path, quiet);
  rp::RoadGraph graph = rp::build_road_graph(network, rp::choose_utm_zone(network), 10.0);
  EXPECT_EQ(graph.zone, kZone);
  rp::compute_geometry_costs(graph, {});
  rp::compute_ranks(graph, {});
  return graph;
}

/// Segments of one OSM way, in the order the segmenter produced them (the way's direction).
std::vector<const rp::Segment*> segments_of(const rp::RoadGraph& graph, std::int64_t way_id) {
  std::vector<const rp::Segment*> out;
  for (const rp::Segment& s : graph.segments) {
    if (graph.osm_way_id(s) == way_id) out.push_back(&s);
  }
  return out;
}

bool has_reason(const rp::Segment& s, const std::string& code) {
  return s.reasons.contains(code);
}

std::string refs(long first, long last) {
  std::string out;
  for (long id = first; id <= last; ++id) out += std::to_string(id) + " ";
  return out;
}

// ---- Arcs drawn in OSM: radius_m within 10 % at 2, 5 and 15 m vertex spacing. ----------------

class OsmArc : public ::testing::TestWithParam<std::tuple<double, double>> {};

TEST_P(OsmArc, RadiusOfTheDrawnArc) {
  const auto [radius_m, spacing_m] = GetParam();
  // Half a circle around (0, 0), vertices `spacing_m` apart along the arc.
  const int steps = static_cast<int>(std::round(kPi * radius_m / spacing_m));
  std::string body;
  for (int i = 0; i <= steps; ++i) {
    const double t = kPi * i / steps;
    body += node_at(100 + i, radius_m * std::cos(t), radius_m * std::sin(t));
  }
  body += rt::osm_way(1, refs(100, 100 + steps), "highway=residential");
  const rp::RoadGraph graph = build(body);
  const double length_m = graph.pieces.at(0).length_m;
  int checked = 0;
  for (const rp::Segment& s : graph.segments) {
    // The dead ends see half a triangle; everything one baseline plus one spacing inside must
    // read the arc's radius.
    const double margin_m = 10.0 + spacing_m;
    const double offset_m = graph.offset_in_piece_m(s);
    if (offset_m < margin_m || offset_m + graph.length_m(s) > length_m - margin_m) continue;
    EXPECT_NEAR(*s.radius_m, radius_m, 0.10 * radius_m) << "at " << offset_m << " m";
    EXPECT_TRUE(radius_m >= 90.0 || has_reason(s, "SHARP_BEND"));
    ++checked;
  }
  EXPECT_GE(checked, 3);
}

INSTANTIATE_TEST_SUITE_P(RadiiAndSpacings, OsmArc,
                         ::testing::Combine(::testing::Values(30.0, 50.0, 100.0, 200.0),
                                            ::testing::Values(2.0, 5.0, 15.0)));

// ---- One way or two ways: the same costs. -----------------------------------------------------

/// A symmetric road: 100 m west-east, a 90 degree left bend of radius 50 m drawn every ~5 m,
/// 100 m south-north. Returns the node list and the index of the node in the middle of the bend.
std::string bend_nodes(std::vector<long>& ids) {
  std::string body;
  const auto add = [&](double e, double n) {
    const long id = 1000 + static_cast<long>(ids.size());
    ids.push_back(id);
    body += node_at(id, e, n);
  };
  add(-100, 0);
  const int steps = 16;  // 78.5 m of arc -> 4.9 m spacing
  for (int i = 0; i <= steps; ++i) {
    const double t = -kPi / 2 + (kPi / 2) * i / steps;  // centre at (0, 50)
    add(50 * std::cos(t), 50 + 50 * std::sin(t));
  }
  add(50, 150);
  return body;
}

std::string join(const std::vector<long>& ids, std::size_t from, std::size_t to, bool reverse) {
  std::string out;
  for (std::size_t k = from; k <= to; ++k)
    out += std::to_string(ids[reverse ? to - (k - from) : k]) + " ";
  return out;
}

TEST(OsmSplit, TwoWaysJoinedAtADegreeTwoNodeGiveTheCostsOfOneWay) {
  std::vector<long> ids;
  const std::string nodes = bend_nodes(ids);
  const std::size_t middle = ids.size() / 2;  // the node in the middle of the bend
  const rp::RoadGraph one =
      build(nodes + rt::osm_way(1, join(ids, 0, ids.size() - 1, false), "highway=residential"));
  // The same road as two ways split mid-bend (e.g. at a maxspeed change), the second one drawn
  // in the opposite direction, as OSM often has it.
  const rp::RoadGraph two = build(
      nodes + rt::osm_way(1, join(ids, 0, middle, false), "highway=residential") +
      rt::osm_way(2, join(ids, middle, ids.size() - 1, true), "highway=residential;maxspeed=30"));
  ASSERT_EQ(two.degree.at(ids[middle]), 2);
  // The road is symmetric, so each half is exactly half the length and the segment boundaries
  // of both builds coincide: 28 segments, the second way's 14 in reverse order.
  ASSERT_EQ(one.segments.size(), 28u);
  ASSERT_EQ(two.segments.size(), 28u);
  for (std::size_t i = 0; i < 28; ++i) {
    const rp::Segment& a = one.segments[i];
    const rp::Segment& b = two.segments[i < 14 ? i : 14 + (27 - i)];
    EXPECT_NEAR(one.length_m(a), two.length_m(b), 0.01) << i;
    EXPECT_NEAR(*a.radius_m, *b.radius_m, 1e-6 * *a.radius_m) << i;
    EXPECT_EQ(*a.curvature_level, *b.curvature_level) << i;
    EXPECT_EQ(*a.curvature_cost, *b.curvature_cost) << i;
    EXPECT_EQ(*a.rank, *b.rank) << i;
    EXPECT_EQ(a.reasons, b.reasons) << i;
    EXPECT_FALSE(b.junction_distance_m.has_value()) << i;  // the join is not a junction
  }
  // The bend itself is seen on both sides of the join: the segments next to the split node.
  EXPECT_NEAR(*two.segments[13].radius_m, 50.0, 5.0);
  EXPECT_NEAR(*two.segments[27].radius_m, 50.0, 5.0);
}

// ---- Junctions by node identity. ----------------------------------------------------------------

TEST(OsmJunctions, TJunctionWhereAWayEndsOnTheInteriorOfAnother) {
  // Way 1: nodes 1 (0,0) - 2 (64,0) - 3 (100,0); way 2 ends on node 2: 2 - 4 (64,44).
  // Node 2: 2 (passing) + 1 (ending) = degree 3. Pieces are cut into ceil(L / 10) equal segments:
  //   1-2: 64 m -> 7 of 64/7 m, midpoints 64 - (k + 1/2) 64/7 m from the junction:
  //        59.43, 50.29, 41.14, 32.00, 22.86, 13.71, 4.57;
  //   2-3: 36 m -> 4 of 9 m: 4.5, 13.5, 22.5, 31.5;   2-4: 44 m -> 5 of 8.8 m: 4.4, 13.2, 22, 30.8,
  //   39.6. None is near the 15 m threshold, so NEAR_JUNCTION is exactly the values below 15.
  const rp::RoadGraph g =
      build(node_at(1, 0, 0) + node_at(2, 64, 0) + node_at(3, 100, 0) + node_at(4, 64, 44) +
            rt::osm_way(1, "1 2 3", "highway=residential") +
            rt::osm_way(2, "2 4", "highway=residential"));
  EXPECT_EQ(g.degree.at(2), 3);
  const auto main = segments_of(g, 1), side = segments_of(g, 2);
  ASSERT_EQ(main.size(), 11u);
  ASSERT_EQ(side.size(), 5u);
  const double expected_main[] = {59.43, 50.29, 41.14, 32.00, 22.86, 13.71,
                                  4.57,  4.5,   13.5,  22.5,  31.5};
  for (std::size_t i = 0; i < main.size(); ++i) {
    EXPECT_NEAR(*main[i]->junction_distance_m, expected_main[i], 0.02) << i;
    EXPECT_EQ(has_reason(*main[i], "NEAR_JUNCTION"), expected_main[i] < 15) << i;
  }
  const double expected_side[] = {4.4, 13.2, 22.0, 30.8, 39.6};
  for (std::size_t i = 0; i < side.size(); ++i) {
    EXPECT_NEAR(*side[i]->junction_distance_m, expected_side[i], 0.02) << i;
    EXPECT_EQ(has_reason(*side[i], "NEAR_JUNCTION"), expected_side[i] < 15) << i;
  }
  // Level 5 where a segment's nearer end is < 20 m (geometry.junction_extent_m) from the
  // junction: on 1-2 the nearer ends are 0, 9.14, 18.29, 27.43, ... m away (main[6], [5], [4]
  // level 5, main[3] not); on 2-3 0, 9, 18, 27 (main[7..9], not main[10]); on 2-4 0, 8.8,
  // 17.6, 26.4 (side[0..2], not side[3]). The others are straight.
  for (const std::size_t i : {4, 5, 6, 7, 8, 9}) EXPECT_EQ(*main[i]->curvature_level, 5) << i;
  for (const std::size_t i : {0, 1, 2, 3, 10}) EXPECT_EQ(*main[i]->curvature_level, 0) << i;
  for (const std::size_t i : {0, 1, 2}) EXPECT_EQ(*side[i]->curvature_level, 5) << i;
  for (const std::size_t i : {3, 4}) EXPECT_EQ(*side[i]->curvature_level, 0) << i;
}

TEST(OsmJunctions, XJunctionAndLookAlikesThatAreNotJunctions) {
  // Way 1 west-east through node 2 at (0,0); way 2 south-north through the same node 2: an X,
  // degree 4. Way 3 crosses way 1 at (30,0) without a shared node (a bridge, say), and way 4 ends
  // at node 31, a different node at exactly the position of way 1's vertex 12 (20,0): neither
  // is a junction, because nodes are matched on identity, never on coordinates.
  const rp::RoadGraph g = build(
      node_at(1, -48, 0) + node_at(2, 0, 0) + node_at(12, 20, 0) + node_at(3, 48, 0) +
      node_at(4, 0, -28) + node_at(5, 0, 28) + node_at(21, 30, -20) + node_at(22, 30, 20) +
      node_at(31, 20, 0) + node_at(32, 20, 40) + rt::osm_way(1, "1 2 12 3", "highway=tertiary") +
      rt::osm_way(2, "4 2 5", "highway=residential") +
      rt::osm_way(3, "21 22", "highway=residential;bridge=yes;layer=1") +
      rt::osm_way(4, "31 32", "highway=service"));
  EXPECT_EQ(g.degree.at(2), 4);
  EXPECT_EQ(g.degree.count(12), 0u);  // an interior vertex used by one way: not a graph node
  EXPECT_EQ(g.degree.at(31), 1);
  // Way 1: pieces 1-2 and 2-3 of 48 m, 5 segments of 9.6 m each, midpoints
  // 48 - (k + 1/2) 9.6 = 43.2, 33.6, 24, 14.4, 4.8 m from the X, then 4.8 .. 43.2 on the other
  // side: the vertex 12 at 20 m and the look-alike node 31 change nothing.
  const auto w1 = segments_of(g, 1);
  ASSERT_EQ(w1.size(), 10u);
  const double expected_w1[] = {43.2, 33.6, 24, 14.4, 4.8, 4.8, 14.4, 24, 33.6, 43.2};
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_NEAR(*w1[i]->junction_distance_m, expected_w1[i], 0.02) << i;
    EXPECT_EQ(has_reason(*w1[i], "NEAR_JUNCTION"), expected_w1[i] < 15) << i;
  }
  // Way 2: 28 m each side of the X, 3 segments of 9.333 m: 23.33, 14, 4.67, then mirrored.
  const auto w2 = segments_of(g, 2);
  ASSERT_EQ(w2.size(), 6u);
  const double expected_w2[] = {23.333, 14, 4.667, 4.667, 14, 23.333};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(*w2[i]->junction_distance_m, expected_w2[i], 0.02) << i;
  }
  // Ways 3 and 4 are roads of their own with no junction on them.
  for (const std::int64_t way : {3, 4}) {
    for (const rp::Segment* s : segments_of(g, way)) {
      EXPECT_FALSE(s->junction_distance_m.has_value()) << way;
      EXPECT_NE(*s->curvature_level, 5) << way;
      EXPECT_FALSE(has_reason(*s, "NEAR_JUNCTION")) << way;
    }
  }
  for (const rp::Segment* s : segments_of(g, 3)) EXPECT_TRUE(s->bridge);
}

TEST(OsmJunctions, TheWindowDoesNotWanderIntoTheSideRoad) {
  // A straight main road (way 2) 1 (0,0) - 2 (145,0) - 3 (290,0) with a side road (way 1, listed
  // first so that a walk from it reaches the junction first) from node 2. Once the side road is
  // straight, once it is a tight 20 m hairpin starting right at the junction. The main road's
  // window goes on through the junction along way 2 but never follows the side road, so its
  // costs are the same with either side road, and symmetric about the junction. By hand, each
  // half has 15 segments of 145/15 = 9.667 m; level 5 (weight 30) on the three of each half
  // whose nearer end is < 20 m from the junction (0, 9.667, 19.33 m): [116, 174] m; the rest
  // 0.75.
  //   segment 0, window [0, 104.83] (a dead end before it): all 0.75 -> 0;
  //   segment 14 ([135.33, 145]), window [40.17, 240.17] through the junction: itself
  //     3 * 9.667 at 30 = 870; [40.17, 135.33]: 19.33 m at 30 + 75.83 m at 0.75 = 636.9;
  //     [145, 240.17]: 29 m at 30 + 66.17 m at 0.75 = 919.6; (870 + 636.9 + 919.6) / (29 +
  //     95.17 + 95.17) = 11.06 -> 11.
  const std::string main = node_at(1, 0, 0) + node_at(2, 145, 0) + node_at(3, 290, 0) +
                           rt::osm_way(2, "1 2 3", "highway=secondary");
  std::string straight_side = node_at(50, 145, 60) + rt::osm_way(1, "2 50", "highway=residential");
  std::string hairpin_side;
  std::string hairpin_refs = "2 ";
  for (int i = 1; i <= 20; ++i) {
    // Half a circle of radius 20 m around (145, 20), from node 2 east and back to (145, 40).
    const double t = -kPi / 2 + kPi * i / 20;
    hairpin_side += node_at(60 + i, 145 + 20 * std::cos(t), 20 + 20 * std::sin(t));
    hairpin_refs += std::to_string(60 + i) + " ";
  }
  hairpin_side += rt::osm_way(1, hairpin_refs, "highway=residential");
  const rp::RoadGraph a = build(main + straight_side), b = build(main + hairpin_side);
  const auto main_a = segments_of(a, 2), main_b = segments_of(b, 2);
  ASSERT_EQ(main_a.size(), 30u);
  ASSERT_EQ(main_b.size(), 30u);
  for (std::size_t i = 0; i < main_a.size(); ++i) {
    EXPECT_EQ(*main_a[i]->radius_m, 10000.0) << i;
    EXPECT_EQ(*main_b[i]->radius_m, 10000.0) << i;
    EXPECT_EQ(*main_a[i]->curvature_cost, *main_b[i]->curvature_cost) << i;
    EXPECT_EQ(*main_a[i]->curvature_cost, *main_a[29 - i]->curvature_cost) << i;
  }
  EXPECT_EQ(*main_a[0]->curvature_cost, 0);
  EXPECT_EQ(*main_a[14]->curvature_cost, 11);
  EXPECT_EQ(*main_a[15]->curvature_cost, 11);
  // The hairpin itself is a sharp bend.
  int sharp = 0;
  for (const rp::Segment* s : segments_of(b, 1)) sharp += has_reason(*s, "SHARP_BEND") ? 1 : 0;
  EXPECT_GE(sharp, 4);
}

// ---- Tags: class, tunnels, bridges, what is not a road, reason order. --------------------------

TEST(OsmTags, StructuresClassesAndTheCanonicalReasonOrder) {
  std::string body;
  long id = 1;
  // Six parallel 30 m ways, 100 m apart, each with its tags.
  const char* const tags[] = {"highway=residential;tunnel=building_passage",
                              "highway=residential;covered=yes",
                              "highway=residential;bridge=yes",
                              "highway=motorway_link;tunnel=yes",
                              "highway=footway",
                              "highway=unclassified;tunnel=no"};
  for (long w = 0; w < 6; ++w) {
    body += node_at(id, 0, 100.0 * static_cast<double>(w)) +
            node_at(id + 1, 30, 100.0 * static_cast<double>(w));
    body += rt::osm_way(w + 1, std::to_string(id) + " " + std::to_string(id + 1), tags[w]);
    id += 2;
  }
  const rp::RoadGraph g = build(body);
  const auto first = [&](std::int64_t way) -> const rp::Segment& {
    return *segments_of(g, way).at(0);
  };
  EXPECT_TRUE(first(1).tunnel);
  EXPECT_EQ(first(1).reasons.list(), std::vector<std::string>{"TUNNEL"});
  EXPECT_TRUE(first(2).tunnel);  // covered=yes is a tunnel for a robot: no view of traffic
  EXPECT_TRUE(first(3).bridge);
  EXPECT_FALSE(first(3).tunnel);
  EXPECT_TRUE(first(3).reasons.empty());
  // Forbidding reasons first: class, then structure.
  EXPECT_EQ(first(4).reasons.list(), (std::vector<std::string>{"NOT_CROSSABLE_CLASS", "TUNNEL"}));
  EXPECT_EQ(*g.class_cost(first(4)), 5);
  EXPECT_TRUE(segments_of(g, 5).empty());  // a footway is not a road
  EXPECT_FALSE(first(6).tunnel);
  EXPECT_EQ(*g.class_cost(first(6)), 1);
  // Straight, no junction, unclassified: rank floor(15 * (70 * 0/14 + 5 * 1/5) / 75) = 0.
  EXPECT_EQ(*first(6).rank, 0);
  EXPECT_EQ(*first(6).score(), 15);
}

}  // namespace
