// Reading and segmentation on tiny hand-written OSM files. Expected lengths come from PROJ:
//   printf "14.4 50.0\n14.4013 50.0\n" | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32633
//   -> 456999.890393961 5538803.17916943 and 457093.056712431 5538802.43257169
// so that way is hypot(93.166318, -0.746598) = 93.1693 m long in the DB's UTM zone 33N.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <osmium/osm/location.hpp>
#include <thread>
#include <vector>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;

namespace {

constexpr double kStraightLength_m = 93.16930;  // see the header comment

struct Built {
  rp::RoadNetwork network;
  rp::RoadGraph graph;
};

Built build(const std::string& body, double max_segment_length_m = 10.0) {
  rt::TempDir dir;
  const std::string path = dir.write("test.osm", rt::osm_document(body));
  rp::Progress quiet(false);
  Built out{rp::read_road_network(path, quiet), {}};
  out.graph =
      rp::build_road_graph(out.network, rp::choose_utm_zone(out.network), max_segment_length_m);
  return out;
}

int degree(const rp::RoadGraph& graph, std::int64_t node) {
  auto it = graph.degree.find(node);
  return it == graph.degree.end() ? 0 : it->second;
}

TEST(Segmentation, StraightWayIsCutIntoEqualSegments) {
  const Built b = build(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.4013) +
                        rt::osm_way(10, "1 2", "highway=residential;name=Straight"));
  EXPECT_EQ(b.graph.zone, (roadcross::geo::UtmZone{33, true}));
  ASSERT_EQ(b.graph.pieces.size(), 1u);
  EXPECT_NEAR(b.graph.pieces[0].length_m, kStraightLength_m, 1e-3);
  // ceil(93.169 / 10) = 10 segments of 9.3169 m.
  ASSERT_EQ(b.graph.segments.size(), 10u);
  for (const rp::Segment& s : b.graph.segments) {
    EXPECT_NEAR(b.graph.length_m(s), kStraightLength_m / 10, 1e-4);
    EXPECT_NEAR(rp::polyline_length_m(b.graph.line(s)), b.graph.length_m(s), 1e-6);
    EXPECT_EQ(b.graph.osm_way_id(s), 10);
    EXPECT_EQ(b.graph.highway(s), "residential");
    EXPECT_EQ(b.graph.name(s), "Straight");
  }
  // Consecutive segments share their end points and graph nodes; the ends are OSM nodes 1, 2.
  EXPECT_EQ(b.graph.from_node_id(b.graph.segments.front()), 1);
  EXPECT_EQ(b.graph.to_node_id(b.graph.segments.back()), 2);
  for (std::size_t i = 1; i < b.graph.segments.size(); ++i) {
    EXPECT_EQ(b.graph.from_node_id(b.graph.segments[i]),
              b.graph.to_node_id(b.graph.segments[i - 1]));
    EXPECT_LT(b.graph.from_node_id(b.graph.segments[i]), 0);  // a split point, not an OSM node
    EXPECT_EQ(b.graph.line(b.graph.segments[i]).front().x,
              b.graph.line(b.graph.segments[i - 1]).back().x);
  }
  EXPECT_EQ(degree(b.graph, 1), 1);
  EXPECT_EQ(degree(b.graph, 2), 1);
}

// The offset is derived from the piece, not stored: segment k of a piece cut into n equal
// parts starts k * length / n from the piece's start, and each piece starts again at 0.
TEST(Segmentation, OffsetInPieceIsTheSumOfTheSegmentsBefore) {
  const Built b =
      build(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.4013) +
            rt::osm_node(3, 50.0, 14.40195) + rt::osm_way(10, "1 2", "highway=residential") +
            rt::osm_way(20, "2 3", "highway=residential"));
  ASSERT_EQ(b.graph.pieces.size(), 2u);
  // Way 10: 93.169 m in 10 segments; way 20, half as long: 46.58 m in ceil(4.658) = 5.
  ASSERT_EQ(b.graph.pieces[0].segment_count, 10u);
  ASSERT_EQ(b.graph.pieces[1].segment_count, 5u);
  for (const rp::RoadPiece& piece : b.graph.pieces) {
    double before_m = 0.0;
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      const rp::Segment& s = b.graph.segments[piece.first_segment + k];
      EXPECT_NEAR(b.graph.offset_in_piece_m(s), kStraightLength_m / 10 * static_cast<double>(k),
                  1e-3);
      EXPECT_NEAR(b.graph.offset_in_piece_m(s), before_m, 1e-9);
      before_m += b.graph.length_m(s);
    }
  }
}

// Ids, end node ids, lengths and the way's columns are derived from the segment's piece and
// index rather than stored. Way 10 (1 -> 2, 10 segments) then way 20 (2 -> 3, 5 segments):
// the segmenter numbered the split points -1, -2, ... in segment order, one after every
// segment but each piece's last, and the ids 1..15.
TEST(Segmentation, DerivedIdsEndNodesAndWayColumns) {
  const Built b = build(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.4013) +
                        rt::osm_node(3, 50.0, 14.40195) +
                        rt::osm_way(10, "1 2", "highway=residential;name=Ten") +
                        rt::osm_way(20, "2 3", "highway=service"));
  const rp::RoadGraph& g = b.graph;
  ASSERT_EQ(g.segments.size(), 15u);
  const std::vector<std::int64_t> from = {1,  -1, -2, -3,  -4,  -5,  -6, -7,
                                          -8, -9, 2,  -10, -11, -12, -13};
  const std::vector<std::int64_t> to = {-1, -2, -3,  -4,  -5,  -6,  -7, -8,
                                        -9, 2,  -10, -11, -12, -13, 3};
  for (std::size_t i = 0; i < g.segments.size(); ++i) {
    const rp::Segment& s = g.segments[i];
    EXPECT_EQ(g.index_of(s), i);
    EXPECT_EQ(g.id_of(s), static_cast<std::int64_t>(i) + 1);
    EXPECT_EQ(g.from_node_id(s), from[i]) << i;
    EXPECT_EQ(g.to_node_id(s), to[i]) << i;
    const bool first_way = i < 10;
    EXPECT_EQ(g.osm_way_id(s), first_way ? 10 : 20) << i;
    EXPECT_EQ(g.highway(s), first_way ? "residential" : "service") << i;
    EXPECT_EQ(g.name(s), first_way ? "Ten" : "") << i;
  }
  // The lengths: the segmenter's arithmetic (equal parts of length / count, the last ending at
  // the piece's end), bit for bit.
  for (const rp::RoadPiece& piece : g.pieces) {
    const double part_m = piece.length_m / static_cast<double>(piece.segment_count);
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      const double start_m = part_m * static_cast<double>(k);
      const double end_m =
          k + 1 == piece.segment_count ? piece.length_m : part_m * static_cast<double>(k + 1);
      EXPECT_EQ(g.length_m(g.segments[piece.first_segment + k]), end_m - start_m) << k;
    }
  }
}

// The two note texts of a segment share one index into a table of the distinct pairs.
TEST(Segmentation, NotesAreSharedPairs) {
  rp::RoadGraph g;
  g.segments.resize(3);
  const std::string* lanes = g.text.intern("lanes");
  const std::string* note = g.text.intern("closed");
  for (const rp::Segment& s : g.segments) {
    EXPECT_EQ(s.notes, 0u);
    EXPECT_EQ(g.context_defaulted(s), nullptr);
    EXPECT_EQ(g.override_note(s), nullptr);
  }
  g.set_context_defaulted(g.segments[0], lanes);
  g.set_context_defaulted(g.segments[1], lanes);
  g.set_override_note(g.segments[1], note);
  g.set_override_note(g.segments[2], note);
  EXPECT_EQ(g.context_defaulted(g.segments[0]), lanes);
  EXPECT_EQ(g.override_note(g.segments[0]), nullptr);
  EXPECT_EQ(g.context_defaulted(g.segments[1]), lanes);
  EXPECT_EQ(g.override_note(g.segments[1]), note);
  EXPECT_EQ(g.context_defaulted(g.segments[2]), nullptr);
  EXPECT_EQ(g.override_note(g.segments[2]), note);
  // Three distinct pairs besides none; the same pair again gets the same index.
  EXPECT_EQ(g.notes.size(), 4u);
  g.set_context_defaulted(g.segments[2], lanes);
  EXPECT_EQ(g.segments[2].notes, g.segments[1].notes);
  g.set_override_note(g.segments[2], nullptr);
  g.set_context_defaulted(g.segments[2], nullptr);
  EXPECT_EQ(g.segments[2].notes, 0u);
  EXPECT_EQ(g.notes.size(), 4u);
}

TEST(Segmentation, MaxSegmentLengthIsRespected) {
  // 93.169 m with a 50 m limit -> 2 segments; with 100 m -> 1.
  const std::string body = rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.4013) +
                           rt::osm_way(10, "1 2", "highway=residential");
  EXPECT_EQ(build(body, 50.0).graph.segments.size(), 2u);
  EXPECT_EQ(build(body, 100.0).graph.segments.size(), 1u);
}

TEST(Segmentation, SegmentCountIsTheFewestPartsWithinTheLimit) {
  EXPECT_EQ(rp::segment_count_of(0.0, 10.0), 1u);  // a zero-length piece is still one segment
  EXPECT_EQ(rp::segment_count_of(9.9, 10.0), 1u);
  EXPECT_EQ(rp::segment_count_of(10.0, 10.0), 1u);
  EXPECT_EQ(rp::segment_count_of(10.1, 10.0), 2u);
  EXPECT_EQ(rp::segment_count_of(20.000000001, 10.0), 2u);  // rounding, not a third part
  EXPECT_EQ(rp::segment_count_of(20.001, 10.0), 3u);
  EXPECT_EQ(rp::segment_count_of(kStraightLength_m, 10.0), 10u);
}

TEST(Segmentation, SegmentTableIsAllocatedAtItsExactSize) {
  // Counted before cutting: capacity == size (a miscount would grow or over-allocate it), and
  // each piece's count is what segment_count_of gives for its length.
  const Built b =
      build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
            rt::osm_node(3, 50.0, 14.401) + rt::osm_node(4, 50.001, 14.4) +
            rt::osm_node(5, 50.0015, 14.4007) + rt::osm_way(10, "1 2 3", "highway=residential") +
            rt::osm_way(20, "2 4 5", "highway=service"));
  ASSERT_EQ(b.graph.pieces.size(), 3u);
  EXPECT_EQ(b.graph.segments.capacity(), b.graph.segments.size());
  EXPECT_EQ(b.graph.pieces.capacity(), b.graph.pieces.size());
  std::size_t expected_first = 0;
  for (const rp::RoadPiece& piece : b.graph.pieces) {
    EXPECT_EQ(piece.segment_count, rp::segment_count_of(piece.length_m, 10.0));
    EXPECT_EQ(piece.first_segment, expected_first);
    expected_first += piece.segment_count;
  }
  EXPECT_EQ(expected_first, b.graph.segments.size());
  // The lines: one after the other, each segment starting where the one before it in its
  // piece ends (the shared point stored once), a piece's first segment on a point of its own.
  std::size_t expected_point = 0;
  for (const rp::RoadPiece& piece : b.graph.pieces) {
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      const rp::Segment& s = b.graph.segments[piece.first_segment + k];
      EXPECT_EQ(s.first_point, expected_point);
      ASSERT_GE(b.graph.line(s).size(), 2u);
      expected_point += b.graph.line(s).size() - 1u;
    }
    ++expected_point;
  }
  EXPECT_EQ(expected_point, b.graph.segment_points.size());
  EXPECT_EQ(b.graph.line(b.graph.segments.front()).front().x, b.graph.pieces[0].points.front().x);
  EXPECT_EQ(b.graph.line(b.graph.segments.back()).back().y, b.graph.pieces[2].points.back().y);
}

TEST(Segmentation, InteriorVerticesAreKept) {
  // A way with a kink at node 2 (1 -> 2 east, 2 -> 3 north, ~0.0005 deg each): one piece,
  // and the segment containing node 2 keeps it as a vertex, so no corner is cut.
  const Built b =
      build(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.4005) +
            rt::osm_node(3, 50.0005, 14.4005) + rt::osm_way(10, "1 2 3", "highway=service"));
  ASSERT_EQ(b.graph.pieces.size(), 1u);
  double total = 0;
  bool kink_kept = false;
  for (const rp::Segment& s : b.graph.segments) {
    total += b.graph.length_m(s);
    EXPECT_NEAR(rp::polyline_length_m(b.graph.line(s)), b.graph.length_m(s), 1e-6);
    if (b.graph.line(s).size() == 3) kink_kept = true;
  }
  EXPECT_NEAR(total, b.graph.pieces[0].length_m, 1e-6);
  EXPECT_TRUE(kink_kept);
}

TEST(Segmentation, TJunctionWhereAWayEndsOnAnotherInterior) {
  // Way 10: 1 - 2 - 3 (east-west); way 20: 2 - 4 ends on 10's interior node 2.
  // Node 2 is matched by id: way 10 is split there (2 pieces), way 20 is 1 piece.
  // Degrees: node 2 = 2 (way 10 passes) + 1 (way 20 ends) = 3 -> a junction.
  const Built b = build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
                        rt::osm_node(3, 50.0, 14.401) + rt::osm_node(4, 50.001, 14.4) +
                        rt::osm_way(10, "1 2 3", "highway=secondary") +
                        rt::osm_way(20, "2 4", "highway=residential"));
  EXPECT_EQ(b.graph.pieces.size(), 3u);
  EXPECT_EQ(degree(b.graph, 2), 3);
  EXPECT_EQ(degree(b.graph, 1), 1);
  EXPECT_EQ(degree(b.graph, 3), 1);
  EXPECT_EQ(degree(b.graph, 4), 1);
}

TEST(Segmentation, TwoCoincidentNodesWithDifferentIdsAreNotAJunction) {
  // Node 5 sits exactly where node 2 is but is a different OSM node: no topology (matching on
  // coordinates would wrongly join the ways).
  const Built b =
      build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
            rt::osm_node(3, 50.0, 14.401) + rt::osm_node(5, 50.0, 14.4) +
            rt::osm_node(4, 50.001, 14.4) + rt::osm_way(10, "1 2 3", "highway=secondary") +
            rt::osm_way(20, "5 4", "highway=residential"));
  EXPECT_EQ(b.graph.pieces.size(), 2u);
  EXPECT_EQ(degree(b.graph, 2), 0);  // interior of way 10, not a graph node
  EXPECT_EQ(degree(b.graph, 5), 1);
}

TEST(Segmentation, CrossingWaysMakeADegreeFourNode) {
  const Built b = build(
      rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) + rt::osm_node(3, 50.0, 14.401) +
      rt::osm_node(4, 50.001, 14.4) + rt::osm_node(5, 49.999, 14.4) +
      rt::osm_way(10, "1 2 3", "highway=tertiary") + rt::osm_way(20, "4 2 5", "highway=tertiary"));
  EXPECT_EQ(b.graph.pieces.size(), 4u);
  EXPECT_EQ(degree(b.graph, 2), 4);
}

TEST(Segmentation, IncidencesListEachNodesPieceEndsInPieceOrder) {
  // The T of TJunctionWhereAWayEndsOnAnotherInterior: pieces in way order, 0 = 1-2 and
  // 1 = 2-3 (way 10 split at 2), 2 = 2-4 (way 20). Node 2 has ends {0 to-end, 1 from-end,
  // 2 from-end}: piece order, and their count is the node's degree.
  const Built b = build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
                        rt::osm_node(3, 50.0, 14.401) + rt::osm_node(4, 50.001, 14.4) +
                        rt::osm_way(10, "1 2 3", "highway=secondary") +
                        rt::osm_way(20, "2 4", "highway=residential"));
  ASSERT_EQ(b.graph.pieces.size(), 3u);
  ASSERT_EQ(b.graph.pieces[0].to_node_id, 2);
  ASSERT_EQ(b.graph.pieces[1].from_node_id, 2);
  ASSERT_EQ(b.graph.pieces[2].to_node_id, 4);
  const rp::Incidences incidences(b.graph);
  EXPECT_EQ(incidences.node_count(), 4u);  // 1, 2, 3, 4
  const auto at_2 = incidences.at(2);
  ASSERT_EQ(at_2.size(), 3u);
  EXPECT_EQ(at_2[0].piece, 0u);
  EXPECT_TRUE(at_2[0].at_end);
  EXPECT_EQ(at_2[1].piece, 1u);
  EXPECT_FALSE(at_2[1].at_end);
  EXPECT_EQ(at_2[2].piece, 2u);
  EXPECT_FALSE(at_2[2].at_end);
  ASSERT_EQ(incidences.at(4).size(), 1u);
  EXPECT_EQ(incidences.at(4)[0].piece, 2u);
  EXPECT_TRUE(incidences.at(4)[0].at_end);
  EXPECT_EQ(incidences.index_of(1), 0u);
  EXPECT_EQ(incidences.index_of(4), 3u);
  EXPECT_TRUE(incidences.at(99).empty());  // not a graph node
  EXPECT_EQ(incidences.index_of(99), rp::Incidences::npos);
  for (const auto& [node, count] : b.graph.degree) {
    EXPECT_EQ(static_cast<int>(incidences.at(node).size()), count) << node;
  }
}

TEST(Segmentation, WaysJoinedEndToEndAreNotAJunction) {
  const Built b =
      build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
            rt::osm_node(3, 50.0, 14.401) + rt::osm_way(10, "1 2", "highway=residential") +
            rt::osm_way(20, "2 3", "highway=residential"));
  EXPECT_EQ(b.graph.pieces.size(), 2u);
  EXPECT_EQ(degree(b.graph, 2), 2);
}

TEST(Segmentation, ClosedRingIsOnePieceWithoutJunction) {
  const Built b = build(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.401) +
                        rt::osm_node(3, 50.001, 14.401) + rt::osm_node(4, 50.001, 14.4) +
                        rt::osm_way(10, "1 2 3 4 1", "highway=residential;junction=roundabout"));
  ASSERT_EQ(b.graph.pieces.size(), 1u);
  EXPECT_EQ(b.graph.pieces[0].from_node_id, 1);
  EXPECT_EQ(b.graph.pieces[0].to_node_id, 1);
  EXPECT_EQ(degree(b.graph, 1), 2);
  EXPECT_TRUE(b.graph.segments.front().oneway);  // roundabouts are one-way
}

TEST(Segmentation, MissingNodeSplitsTheWayAndIsCounted) {
  // Node 99 is referenced but not in the file (cut off by the extract). 1-2 stays a piece,
  // 3 alone is dropped.
  const Built b =
      build(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
            rt::osm_node(3, 50.0, 14.401) + rt::osm_way(10, "1 2 99 3", "highway=residential"));
  EXPECT_EQ(b.network.missing_locations, 1u);
  EXPECT_EQ(b.graph.dropped_node_refs, 1u);
  ASSERT_EQ(b.graph.pieces.size(), 1u);
  EXPECT_EQ(b.graph.pieces[0].to_node_id, 2);
}

TEST(Segmentation, NonRoadsAreIgnored) {
  const std::string nodes =
      rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) + rt::osm_node(3, 50.0, 14.401);
  const Built b =
      build(nodes + rt::osm_way(10, "1 2", "highway=residential") +
            rt::osm_way(11, "2 3", "highway=footway;footway=crossing") +
            rt::osm_way(12, "2 3", "highway=cycleway") + rt::osm_way(13, "2 3", "highway=path") +
            rt::osm_way(14, "2 3", "highway=steps") + rt::osm_way(15, "2 3", "highway=track") +
            rt::osm_way(16, "2 3", "highway=construction") +
            rt::osm_way(17, "1 2 3 1", "highway=service;area=yes") +
            rt::osm_way(18, "2 3", "building=yes"));
  ASSERT_EQ(b.network.ways.size(), 1u);
  EXPECT_EQ(b.network.ways[0].osm_id, 10);
  EXPECT_EQ(b.network.ways_read, 9u);
  EXPECT_EQ(degree(b.graph, 2), 1);  // the footway etc. do not make node 2 a junction
}

TEST(Segmentation, KeptRoadClasses) {
  for (const char* kept :
       {"motorway", "trunk_link", "primary", "secondary_link", "tertiary", "unclassified",
        "residential", "service", "busway", "road", "living_street"}) {
    EXPECT_TRUE(rp::is_kept_road_class(kept)) << kept;
  }
  for (const char* ignored : {"footway", "cycleway", "path", "steps", "track", "construction",
                              "pedestrian", "bridleway", "proposed", ""}) {
    EXPECT_FALSE(rp::is_kept_road_class(ignored)) << ignored;
  }
}

TEST(Segmentation, FileWithoutRoadsIsAnError) {
  rt::TempDir dir;
  const std::string path = dir.write(
      "no_roads.osm", rt::osm_document(rt::osm_node(1, 50.0, 14.4) + rt::osm_node(2, 50.0, 14.401) +
                                       rt::osm_way(10, "1 2", "highway=footway")));
  rp::Progress quiet(false);
  try {
    rp::read_road_network(path, quiet);
    FAIL() << "expected InputError";
  } catch (const rp::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("none is a road"), std::string::npos);
  }
}

// The ways pass sorts each way by its highway, footway, cycleway and area tags (read in one walk
// over its tags): kept roads, crossing ways (footway or cycleway=crossing, not areas) and
// pavements mapped on their own (highway=footway/path/cycleway with footway=sidewalk, not
// areas); the rest is dropped. Expected ids by hand from the tags below.
TEST(ReadRoadNetwork, WaysSortedByTheirHighwayFootwayCyclewayAndAreaTags) {
  std::string body;
  for (long n = 1; n <= 4; ++n) body += rt::osm_node(n, 50.0, 14.4 + 0.0005 * double(n));
  body += rt::osm_way(10, "1 2", "highway=residential;name=Road");
  body += rt::osm_way(11, "2 3", "area=yes;highway=residential");                // an area: dropped
  body += rt::osm_way(12, "1 2", "highway=footway;footway=sidewalk");            // pavement
  body += rt::osm_way(13, "2 3", "footway=sidewalk;highway=path");               // pavement
  body += rt::osm_way(14, "3 4", "highway=cycleway;footway=sidewalk;area=yes");  // an area
  body += rt::osm_way(15, "3 4", "highway=steps;footway=sidewalk");              // not walkable way
  body += rt::osm_way(16, "2 3", "highway=footway;footway=crossing");            // crossing
  body += rt::osm_way(17, "3 4", "cycleway=crossing;highway=cycleway");          // crossing
  body += rt::osm_way(18, "1 3", "footway=crossing;area=yes");                   // an area
  body += rt::osm_way(19, "1 4", "building=yes;amenity=cafe");                   // neither
  body += rt::osm_way(20, "3 4", "highway=service;area=no");                     // road
  rt::TempDir dir;
  const std::string path = dir.write("ways.osm", rt::osm_document(body));
  rp::Progress quiet(false);
  const rp::RoadNetwork network = rp::read_road_network(path, quiet);
  const auto ids = [](const auto& ways) {
    std::vector<std::int64_t> out;
    for (const auto& way : ways) out.push_back(way.osm_id);
    return out;
  };
  EXPECT_EQ(network.ways_read, 11u);
  EXPECT_EQ(ids(network.ways), (std::vector<std::int64_t>{10, 20}));
  EXPECT_EQ(ids(network.sidewalk_ways), (std::vector<std::int64_t>{12, 13}));
  EXPECT_EQ(ids(network.crossing_ways), (std::vector<std::int64_t>{16, 17}));
  EXPECT_EQ(network.ways[0].highway, "residential");
  EXPECT_EQ(network.ways[1].highway, "service");
}

/// An extra reader whose ways_done() takes a while: the node pass must hand it every node, in
/// file order, and none before ways_done() has returned (the nodes read meanwhile wait).
class SlowExtraReader final : public rp::ExtraOsmReader {
 public:
  void way(const osmium::Way&) override { ++ways; }
  void ways_done() override {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    done.store(true);
  }
  void node(std::int64_t id, osmium::Location location) override {
    if (!done.load()) ++before_ways_done;
    ids.push_back(id);
    if (location.valid()) lons.push_back(location.lon());
  }
  int ways = 0, before_ways_done = 0;
  std::atomic<bool> done{false};
  std::vector<std::int64_t> ids;
  std::vector<double> lons;
};

TEST(ReadRoadNetwork, NodesReadWhileWaysDoneRunsWaitAndComeInOrder) {
  std::string body;
  for (long n = 1; n <= 3000; ++n) body += rt::osm_node(n, 50.0, 14.4 + 1e-5 * double(n));
  body += rt::osm_way(10, "1 2 3", "highway=residential");
  rt::TempDir dir;
  const std::string path = dir.write("nodes.osm", rt::osm_document(body));
  rp::Progress quiet(false);
  SlowExtraReader extra;
  const rp::RoadNetwork network = rp::read_road_network(path, quiet, &extra);
  EXPECT_EQ(extra.ways, 1);
  EXPECT_EQ(extra.before_ways_done, 0);
  ASSERT_EQ(extra.ids.size(), 3000u);
  for (std::size_t i = 0; i < extra.ids.size(); ++i) ASSERT_EQ(extra.ids[i], std::int64_t(i) + 1);
  ASSERT_EQ(extra.lons.size(), 3000u);
  EXPECT_NEAR(extra.lons[2999], 14.43, 1e-7);
  EXPECT_EQ(network.locations.size(), 3u);  // the road's own nodes, as without the extra reader
}

}  // namespace
