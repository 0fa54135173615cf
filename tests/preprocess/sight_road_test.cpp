// The road the sight stage follows from a segment (sight/road.hpp, issue 27): RoadFollower
// followed a little at a time gives the path of one walk to the range, bit for bit, and stops
// where it is asked to (lengths worked out by hand); LegLengths gives each leg's length and
// keeps the right piece's when two pieces share a slot.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/sight/road.hpp"
#include "ways_graph.hpp"

namespace rp = roadcross::preprocess;
namespace sd = roadcross::preprocess::sight_detail;
namespace geo = roadcross::geo;
using roadcross::schema::PlanePoint;

namespace {

const geo::UtmZone kZone{33, true};
constexpr double kE0 = 500000.0, kN0 = 5540000.0;

/// Residential ways through UTM offsets from (kE0, kN0); equal points are one node.
rp::RoadGraph graph_of_ways(const std::vector<std::vector<PlanePoint>>& ways) {
  return roadcross::testing::graph_of_ways(ways, 20.0, kZone, kE0, kN0);
}

/// The road tables the sight stage builds once, and a follower over them.
struct Roads {
  explicit Roads(const rp::RoadGraph& g)
      : graph(g), incidences(rp::incidences_of(g)), nodes(sd::end_nodes(g, incidences)) {
    for (const rp::RoadPiece& piece : g.pieces)
      cumulative.push_back(sd::cumulative_m(piece.points));
    leaving = sd::leaving_directions(g);
  }
  sd::RoadFollower follower(double range_m, sd::Path& path, sd::LegLengths& legs) const {
    return sd::RoadFollower(graph, incidences, nodes, cumulative, leaving, range_m, path, legs);
  }
  const rp::RoadGraph& graph;
  rp::Incidences incidences;
  std::vector<std::array<std::uint32_t, 2>> nodes;
  std::vector<std::vector<double>> cumulative;
  std::vector<std::array<PlanePoint, 2>> leaving;
};

/// The piece whose first point is nearest to the offset (x, y).
std::size_t piece_from(const rp::RoadGraph& graph, double x, double y) {
  std::size_t best = 0;
  double best_m = INFINITY;
  for (std::size_t i = 0; i < graph.pieces.size(); ++i) {
    const PlanePoint& p = graph.pieces[i].points.front();
    const double d = std::hypot(p.x - kE0 - x, p.y - kN0 - y);
    if (d < best_m) best_m = d, best = i;
  }
  return best;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

}  // namespace

TEST(SightRoad, FollowsOnlyAsFarAsAskedAndOnThroughTheStraightestContinuation) {
  // Three ways meet at (0, 0): west (-200, 0)-(0, 0), east (0, 0)-(300, 10), north
  // (0, 0)-(0, 300). From x = -30 on the west way towards its end the road reaches the node after
  // 30 m and goes on east (the straightest way), ending at (300, 10) 30 + hypot(300, 10) m out.
  const rp::RoadGraph graph =
      graph_of_ways({{{-200, 0}, {0, 0}}, {{0, 0}, {300, 10}}, {{0, 0}, {0, 300}}});
  const Roads roads(graph);
  sd::Path path;
  sd::LegLengths legs;
  sd::RoadFollower road = roads.follower(300.0, path, legs);
  road.start(piece_from(graph, -200, 0), 170.0, true);
  ASSERT_EQ(path.points.size(), 1u);
  EXPECT_NEAR(path.points[0].x - kE0, -30.0, 1e-6);
  road.extend_beyond(10.0);  // the node at 30 m is the first vertex beyond 10 m
  ASSERT_EQ(path.points.size(), 2u);
  EXPECT_NEAR(path.length_m(), 30.0, 1e-6);
  road.extend_beyond(29.0);  // already beyond
  EXPECT_EQ(path.points.size(), 2u);
  road.extend_beyond(100.0);  // on east, past the range at (300, 10)
  ASSERT_EQ(path.points.size(), 3u);
  EXPECT_NEAR(path.points[2].x - kE0, 300.0, 1e-6);
  EXPECT_NEAR(path.points[2].y - kN0, 10.0, 1e-6);
  EXPECT_NEAR(path.length_m(), 30.0 + std::hypot(300.0, 10.0), 1e-6);
  road.extend_to_range();  // the range is reached: nothing more
  EXPECT_EQ(path.points.size(), 3u);
}

TEST(SightRoad, FollowedInStepsItIsTheWalkToTheRangeBitForBit) {
  // A ring of 4 x 50 m (walked round again: shorter than the range), a spur off it with a
  // dead end, and a bent way with several vertices; every piece, from several positions, both
  // ways, followed in steps of 7 m against one walk to the range.
  const rp::RoadGraph graph = graph_of_ways({{{0, 0}, {50, 0}, {50, 50}, {0, 50}, {0, 0}},
                                             {{50, 0}, {120, -5}, {180, 20}, {260, 20}},
                                             {{0, 50}, {-30, 90}}});
  const Roads roads(graph);
  sd::LegLengths legs;  // shared by every follower, as a thread's
  int compared = 0;
  for (std::size_t piece = 0; piece < graph.pieces.size(); ++piece) {
    const double length_m = roads.cumulative[piece].back();
    for (const double at : {0.0, 0.3, 0.5, 0.9, 1.0}) {
      for (const bool towards_end : {true, false}) {
        sd::Path whole, stepped;
        sd::RoadFollower one = roads.follower(300.0, whole, legs);
        sd::RoadFollower steps = roads.follower(300.0, stepped, legs);
        one.start(piece, at * length_m, towards_end);
        steps.start(piece, at * length_m, towards_end);
        one.extend_to_range();
        for (double limit_m = 0.0; limit_m < 400.0; limit_m += 7.0) {
          steps.extend_beyond(limit_m);
          // Never more than asked: the last point is the first beyond the limit.
          if (stepped.points.size() > 2) {
            EXPECT_LE(stepped.at_m[stepped.at_m.size() - 2], limit_m);
          }
        }
        ASSERT_EQ(stepped.points.size(), whole.points.size());
        for (std::size_t i = 0; i < whole.points.size(); ++i) {
          EXPECT_TRUE(same_bits(stepped.points[i].x, whole.points[i].x));
          EXPECT_TRUE(same_bits(stepped.points[i].y, whole.points[i].y));
          EXPECT_TRUE(same_bits(stepped.at_m[i], whole.at_m[i]));
          // Each step is the hypot of its two points, as Path::add takes it.
          if (i > 0) {
            EXPECT_TRUE(same_bits(
                whole.at_m[i],
                whole.at_m[i - 1] + sd::distance_m(whole.points[i - 1], whole.points[i])));
          }
        }
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, static_cast<int>(graph.pieces.size()) * 10);
}

TEST(SightRoad, LegLengthsOfTheRightPieceWhenTwoShareASlot) {
  rp::RoadPiece a, b;
  a.points = {{0, 0}, {3, 4}, {3, 10}};  // legs 5 and 6
  b.points = {{1, 1}, {1, 3}};           // leg 2
  sd::LegLengths legs;
  EXPECT_EQ(legs.of(5, a), (std::vector<double>{5.0, 6.0}));
  EXPECT_EQ(legs.of(5 + 256, b), (std::vector<double>{2.0}));  // the same slot
  EXPECT_EQ(legs.of(5, a), (std::vector<double>{5.0, 6.0}));   // a's again
  EXPECT_EQ(legs.of(6, b), (std::vector<double>{2.0}));
  EXPECT_EQ(legs.of(5, a), (std::vector<double>{5.0, 6.0}));
}
