// Sight distance (issue 11) on roads whose answer is known: a straight flat road (the range
// limit), a wall across it, an L-shaped road with a building in the inside of the corner
// (by hand), a road over a Gaussian hill (from the analytic surface) and the same hill seen by a
// sensor raised above its crest; and the whole build reading buildings from OSM.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/preprocess/sight/sight.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/sqlite.hpp"
#include "ways_graph.hpp"

namespace rp = roadcross::preprocess;
namespace geo = roadcross::geo;
using roadcross::schema::PlanePoint;
using roadcross::testing::TempDir;

namespace {

const geo::UtmZone kZone{33, true};
// On zone 33's central meridian, where grid north is true north.
constexpr double kE0 = 500000.0, kN0 = 5540000.0;

/// The ways' graph (tests/support/ways_graph.hpp) at (kE0, kN0), cut into segments of at most
/// `segment_m`.
rp::RoadGraph graph_of_ways(const std::vector<std::vector<PlanePoint>>& ways, double segment_m) {
  return roadcross::testing::graph_of_ways(ways, segment_m, kZone, kE0, kN0);
}

/// One way through `offsets`.
rp::RoadGraph graph_of(const std::vector<PlanePoint>& offsets, double segment_m) {
  return graph_of_ways({offsets}, segment_m);
}

/// The segment whose midpoint is nearest to the offset (x, y).
const rp::Segment& segment_at(const rp::RoadGraph& graph, double x, double y) {
  const rp::Segment* best = &graph.segments.front();
  double best_d = 1e300;
  for (const rp::Segment& s : graph.segments) {
    const PlanePoint& a = graph.line(s).front();
    const PlanePoint& b = graph.line(s).back();
    const double d = std::hypot(0.5 * (a.x + b.x) - kE0 - x, 0.5 * (a.y + b.y) - kN0 - y);
    if (d < best_d) best_d = d, best = &s;
  }
  return *best;
}

rp::ObstacleEdge edge(double ax, double ay, double bx, double by, double top_m,
                      double bottom_m = 0.0) {
  return {{kE0 + ax, kN0 + ay}, {kE0 + bx, kN0 + by}, float(bottom_m), float(top_m)};
}

/// The four edges of the box [x0, x1] x [y0, y1] (offsets), `top_m` high.
std::vector<rp::ObstacleEdge> box(double x0, double y0, double x1, double y1, double top_m) {
  return {edge(x0, y0, x1, y0, top_m), edge(x1, y0, x1, y1, top_m), edge(x1, y1, x0, y1, top_m),
          edge(x0, y1, x0, y0, top_m)};
}

}  // namespace

TEST(Sight, ParsesHeightTags) {
  EXPECT_DOUBLE_EQ(rp::parse_height_m("12"), 12.0);
  EXPECT_DOUBLE_EQ(rp::parse_height_m("12.5 m"), 12.5);
  EXPECT_DOUBLE_EQ(rp::parse_height_m("7m"), 7.0);
  EXPECT_DOUBLE_EQ(rp::parse_height_m("10 ft"), 3.048);
  EXPECT_TRUE(std::isnan(rp::parse_height_m("tall")));
  EXPECT_TRUE(std::isnan(rp::parse_height_m("")));
  EXPECT_TRUE(std::isnan(rp::parse_height_m("-3")));
  EXPECT_TRUE(std::isnan(rp::parse_height_m("3 storeys")));
}

TEST(Sight, StraightFlatRoadSeesToTheRangeLimit) {
  rp::RoadGraph graph = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  const rp::SightParameters p;
  const rp::SightReport report = rp::compute_sight(graph, nullptr, {}, p);
  EXPECT_EQ(report.segments, graph.segments.size());
  EXPECT_EQ(report.limited, 0u);
  // Every segment, the ends included: no vehicle comes from beyond a dead end unseen.
  for (const rp::Segment& s : graph.segments) {
    EXPECT_FLOAT_EQ(*s.sight_forward_m, 300.0f);
    EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);
    EXPECT_FLOAT_EQ(*s.sight_min_m, 300.0f);
    // 50 km/h over (6 m / 1 m/s + 1 s start-up + 1 s margin) = 13.89 m/s * 8 s = 111.1 m.
    EXPECT_NEAR(*s.required_sight_m, 50.0 / 3.6 * 8.0, 1e-3);
    EXPECT_FALSE(s.reasons.contains("LIMITED_VISIBILITY"));
  }
}

TEST(Sight, WallAcrossTheRoadCutsTheViewAndALowOneDoesNot) {
  const rp::SightParameters p;
  // A 3 m wall across the road 100 m east of the segment at x = 10 (its midpoint), from
  // y = -20 to 20: a vehicle beyond it is hidden; the view ends at the wall.
  rp::RoadGraph graph = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  rp::compute_sight(graph, nullptr, {edge(110, -20, 110, 20, 3.0)}, p);
  const rp::Segment& s = segment_at(graph, 10, 0);
  EXPECT_NEAR(*s.sight_forward_m, 100.0, 0.1);
  EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);
  EXPECT_TRUE(s.reasons.contains("LIMITED_VISIBILITY"));  // 100 < 111.1
  // A 0.5 m kerb wall is below every sight line (0.6 m sensor, 1.1 m object): nothing hidden.
  rp::RoadGraph low = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  rp::compute_sight(low, nullptr, {edge(110, -20, 110, 20, 0.5)}, p);
  EXPECT_FLOAT_EQ(*segment_at(low, 10, 0).sight_forward_m, 300.0f);
  // A building on pillars (opaque from 4 m up) does not hide a car under it either.
  rp::RoadGraph pillars = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  rp::compute_sight(pillars, nullptr, {edge(110, -20, 110, 20, 20.0, 4.0)}, p);
  EXPECT_FLOAT_EQ(*segment_at(pillars, 10, 0).sight_forward_m, 300.0f);
}

TEST(Sight, WallsOnGridCellBoundariesAndALongDiagonalWall) {
  // The sight stage buckets edges in 16 m cells; kE0 and kN0 are multiples of 16, so these
  // walls lie exactly on cell boundaries, where a rounding slip would lose them.
  const rp::SightParameters p;
  // A wall across an east-west road at x = 112 (a column boundary): the view from the segment
  // at x = 10 ends 102 m east.
  rp::RoadGraph east = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  rp::compute_sight(east, nullptr, {edge(112, -20, 112, 20, 3.0)}, p);
  EXPECT_NEAR(*segment_at(east, 10, 0).sight_forward_m, 102.0, 0.1);
  EXPECT_FLOAT_EQ(*segment_at(east, 10, 0).sight_backward_m, 300.0f);
  // A wall across a north-south road at y = 112 (a row boundary): 102 m north of y = 10.
  rp::RoadGraph north = graph_of({{0, -1000}, {0, 1000}}, 20.0);
  rp::compute_sight(north, nullptr, {edge(-20, 112, 20, 112, 3.0)}, p);
  const rp::Segment& n = segment_at(north, 0, 10);
  EXPECT_NEAR(std::min(*n.sight_forward_m, *n.sight_backward_m), 102.0, 0.1);
  EXPECT_FLOAT_EQ(std::max(*n.sight_forward_m, *n.sight_backward_m), 300.0f);
  // A 1 km wall crossing the road obliquely (x = 110 + 0.1 y, through ~60 rows of cells). By
  // hand, from either kerb (y = +-3, x = 10) the line to a vehicle at (X, 0) meets the wall
  // before the vehicle exactly when X >= 110: the view ends 100 m east.
  rp::RoadGraph oblique = graph_of({{-1000, 0}, {1000, 0}}, 20.0);
  rp::compute_sight(oblique, nullptr, {edge(60, -500, 160, 500, 3.0)}, p);
  EXPECT_NEAR(*segment_at(oblique, 10, 0).sight_forward_m, 100.0, 0.1);
}

TEST(Sight, LShapedRoadWithABuildingInTheCorner) {
  // The road runs east along y = 0 from x = -200 to the corner (0, 0), then north to (0, 200);
  // one way, so the corner is a vertex and the road continues round it. 20 m segments: the one
  // 30 m before the corner has its midpoint at x = -30. A 10 m building fills the inside of the
  // corner: x in [-100, -10], y in [10, 100]. Default width 6 m: the kerbs are at y = +-3.
  //
  // By hand, looking ahead (east, then north) at a vehicle at (0, s) past the corner: the line
  // from the north kerb (-30, 3) reaches x = -10 (the building's east face) at 20/30 of its
  // run, at y = 3 + (2/3)(s - 3); it touches the building's corner (-10, 10) when that is 10:
  // s = 3 + 7 * 3/2 = 13.5 m, and for larger s it passes through the building. From the south
  // kerb (-30, -3): -3 + (2/3)(s + 3) = 10 gives s = 16.5 m. The worse kerb counts: the view
  // reaches 30 m to the corner + 13.5 m = 43.5 m along the road.
  rp::RoadGraph graph = graph_of({{-200, 0}, {0, 0}, {0, 200}}, 20.0);
  const rp::SightParameters p;
  rp::compute_sight(graph, nullptr, box(-100, 10, -10, 100, 10.0), p);
  const rp::Segment& s = segment_at(graph, -30, 0);
  EXPECT_NEAR(*s.sight_forward_m, 43.5, 0.1);
  // Backwards: 170 m of open road to a dead end, nothing hidden: the range limit.
  EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);
  EXPECT_FLOAT_EQ(*s.sight_min_m, *s.sight_forward_m);
  EXPECT_TRUE(s.reasons.contains("LIMITED_VISIBILITY"));
  // Without the building the corner hides nothing (flat, open).
  rp::RoadGraph open = graph_of({{-200, 0}, {0, 0}, {0, 200}}, 20.0);
  rp::compute_sight(open, nullptr, {}, p);
  EXPECT_FLOAT_EQ(*segment_at(open, -30, 0).sight_forward_m, 300.0f);
}

TEST(Sight, ABuildingBetweenTheKerbAndTheRoadBeyondABend) {
  // The road runs east along y = 0 to the corner (0, 0), then 200 m north-east along y = x (400 m
  // in all: 20 segments of 20 m). The robot stands at the segment whose midpoint is x = -30, its
  // kerbs at (-30, +-3). A 10 m building x in [-20, -10], y in [5, 15] stands inside the bend,
  // between the north kerb and the road beyond the corner.
  //
  // By hand, a vehicle at (c, c) past the corner (s = c sqrt 2 along the diagonal): the line from
  // the north kerb (-30, 3) crosses x = -10 at y = 3 + 20 (c - 3) / (c + 30), which reaches the
  // building's corner (-10, 5) when 18 c = 120, c = 6.667; beyond, it runs through the building
  // (it meets y = 5 at x = -30 + 2 (c + 30) / (c - 3) in [-20, -10] up to c = 11.25, then the
  // west wall below y = 13). From the south kerb (-30, -3): -3 + 20 (c + 3) / (c + 30) = 5 at
  // c = 15, later. The worse kerb sees 30 m to the corner and 6.667 sqrt 2 = 9.428 m beyond:
  // 39.43 m (the 5 m steps find it hidden at 40 m; the bisection stops 8 cm short at most).
  const double diagonal = 200.0 / std::sqrt(2.0);
  const std::vector<PlanePoint> road{{-200, 0}, {0, 0}, {diagonal, diagonal}};
  rp::RoadGraph graph = graph_of(road, 20.0);
  const rp::SightParameters p;
  rp::compute_sight(graph, nullptr, box(-20, 5, -10, 15, 10.0), p);
  const rp::Segment& s = segment_at(graph, -30, 0);
  EXPECT_NEAR(*s.sight_forward_m, 30.0 + 20.0 / 3.0 * std::sqrt(2.0) - 0.04, 0.05);
  EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);  // 170 m of open road to a dead end
  // The building raised on pillars 2 m high: every line passes under it (at most 1.1 m high).
  rp::RoadGraph raised = graph_of(road, 20.0);
  std::vector<rp::ObstacleEdge> pillars = box(-20, 5, -10, 15, 10.0);
  for (rp::ObstacleEdge& e : pillars) e.bottom_m = 2.0f;
  rp::compute_sight(raised, nullptr, pillars, p);
  EXPECT_FLOAT_EQ(*segment_at(raised, -30, 0).sight_forward_m, 300.0f);
}

TEST(Sight, FollowsTheStraightestContinuationThroughAJunction) {
  // Three ways meet at (0, 0): west (-200, 0)-(0, 0), east (0, 0)-(300, 10) (a 1.9 degree
  // turn) and north (0, 0)-(0, 300) (90 degrees). Looking east from the segment at x = -30, the
  // walk goes on east. A 3 m wall across the east road at x = 100 ends the view at 130 m; the
  // same wall across the north road (at y = 100) hides nothing on the way the walk takes.
  const std::vector<std::vector<PlanePoint>> ways = {
      {{-200, 0}, {0, 0}}, {{0, 0}, {300, 10}}, {{0, 0}, {0, 300}}};
  const rp::SightParameters p;
  rp::RoadGraph east = graph_of_ways(ways, 20.0);
  rp::compute_sight(east, nullptr, {edge(100, -20, 100, 30, 3.0)}, p);
  const rp::Segment& s = segment_at(east, -30, 0);
  // The wall cuts the east road at x = 100, 100 * 10/300 = 3.3 m north of the axis: along the
  // road 30 + sqrt(100^2 + 3.33^2) = 130.06 m.
  EXPECT_NEAR(*s.sight_forward_m, 30.0 + std::hypot(100.0, 100.0 / 30.0), 0.1);
  rp::RoadGraph north = graph_of_ways(ways, 20.0);
  rp::compute_sight(north, nullptr, {edge(-20, 100, 20, 100, 3.0)}, p);
  EXPECT_FLOAT_EQ(*segment_at(north, -30, 0).sight_forward_m, 300.0f);
}

namespace {

double gaussian_hill(double x, double y) {  // offsets from (kE0, kN0); 50 m high, sigma 100 m
  return 300.0 + 50.0 * std::exp(-(x * x + y * y) / (2 * 100.0 * 100.0));
}

rp::Grid hill_grid(double cell_m) {
  rp::Grid grid(
      rp::grid_covering(kZone, kE0 - 1000, kN0 - 1000, kE0 + 1000, kN0 + 1000, 0.0, cell_m));
  for (std::size_t row = 0; row < grid.spec.rows; ++row) {
    for (std::size_t col = 0; col < grid.spec.cols; ++col) {
      grid.at(col, row) = static_cast<float>(
          gaussian_hill(grid.spec.centre_easting(col) - kE0, grid.spec.centre_northing(row) - kN0));
    }
  }
  return grid;
}

/// The sight distance over the analytic hill with its height scaled by `scale`, independently
/// of the implementation: from the kerb (x0, kerb_y) a vehicle at (x0 + d, 0) is hidden when
/// the surface reaches the line anywhere (1000 points a line); d in 5 cm steps up to range_m.
double analytic_sight_m(double x0, double kerb_y, double sensor_m, double object_m, double range_m,
                        double scale = 1.0) {
  const auto z = [&](double x, double y) { return 300.0 + scale * (gaussian_hill(x, y) - 300.0); };
  const double ez = z(x0, kerb_y) + sensor_m;
  for (double d = 0.05; d <= range_m; d += 0.05) {
    const double tx = x0 + d, tz = z(tx, 0.0) + object_m;
    for (int k = 1; k < 1000; ++k) {
      const double t = k / 1000.0;
      if (z(x0 + t * d, kerb_y * (1.0 - t)) >= ez + t * (tz - ez)) return d - 0.05;
    }
  }
  return range_m;
}

}  // namespace

TEST(Sight, CrestOfAGaussianHillLimitsTheViewFromItsFoot) {
  // The road runs east over the hill's top; the robot stands at the segment whose midpoint is
  // x = -190 (near the foot, where the slope turns concave at sigma = 100 m).
  rp::RoadGraph graph = graph_of({{-600, 0}, {600, 0}}, 20.0);
  const rp::Grid grid = hill_grid(5.0);
  const rp::SightParameters p;
  rp::compute_sight(graph, &grid, {}, p);
  const rp::Segment& s = segment_at(graph, -190, 0);
  // The hill is symmetric about y = 0, so both kerbs (y = +-3) see the same. The vehicle
  // climbing the near flank disappears over the convex shoulder (|x| < sigma) some 35 m before
  // the top: the analytic answer is 155.3 m. The grid is a bilinear interpolation of 5 m
  // samples, which lies below a convex surface by at most h^2/8 |f''| per axis: 25/8 * 0.005 *
  // 2 = 0.03 m (f'' = 50/100^2); the line is sampled every 5 m, which misses the tangent point
  // by at most 2.5 m: 0.5 * 0.005 * 2.5^2 = 0.016 m. How far 0.05 m of height moves the answer
  // is computed below (the hill's height scaled by 1 +- 0.05/50); the tolerance is that spread
  // plus the bisection's 8 cm and the reference's 5 cm steps.
  const double exact = analytic_sight_m(-190, 3, 0.6, 1.1, 300);
  EXPECT_LT(exact, 250.0);  // the crest limits it
  EXPECT_GT(exact, 150.0);
  const double high_hill = analytic_sight_m(-190, 3, 0.6, 1.1, 300, 1.0 + 0.05 / 50.0);
  const double low_hill = analytic_sight_m(-190, 3, 0.6, 1.1, 300, 1.0 - 0.05 / 50.0);
  EXPECT_NEAR(*s.sight_forward_m, exact, 0.15 + std::abs(low_hill - high_hill));
  // Looking back west, down to the plain: nothing hides a vehicle.
  EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);
}

TEST(Sight, SensorRaisedAboveTheCrestSeesOverIt) {
  rp::RoadGraph graph = graph_of({{-600, 0}, {600, 0}}, 20.0);
  const rp::Grid grid = hill_grid(5.0);
  rp::SightParameters p;
  // 200 m up: the eye at 507 m, the top at 350 m; the line to a vehicle at the range limit
  // (x = 110, 1.1 m above 330 m) passes 360 m over x = 50 (hill 344 m).
  p.sensor_height_m = 200.0;
  EXPECT_DOUBLE_EQ(analytic_sight_m(-190, 3, 200.0, 1.1, 300), 300.0);
  rp::compute_sight(graph, &grid, {}, p);
  const rp::Segment& s = segment_at(graph, -190, 0);
  EXPECT_FLOAT_EQ(*s.sight_forward_m, 300.0f);
  EXPECT_FLOAT_EQ(*s.sight_backward_m, 300.0f);
}

TEST(Sight, RankPenaltyOnlyInCostMode) {
  rp::RoadGraph graph = graph_of({{-200, 0}, {0, 0}, {0, 200}}, 20.0);
  rp::SightParameters p;
  rp::compute_sight(graph, nullptr, box(-100, 10, -10, 100, 10.0), p);
  for (rp::Segment& s : graph.segments) s.rank = 2;
  rp::apply_sight_rank_penalty(graph, p);  // unsuitable mode: the runtime decides, rank stays
  EXPECT_EQ(*segment_at(graph, -30, 0).rank, 2);
  p.limited_visibility_unsuitable = 0.0;
  rp::apply_sight_rank_penalty(graph, p);
  EXPECT_EQ(*segment_at(graph, -30, 0).rank, 6);
  EXPECT_EQ(*segment_at(graph, -30, 0).score(), 9);
}

namespace {

std::string node_at(long id, double x, double y, const std::string& tags = "") {
  const geo::LatLon ll = geo::utm_to_wgs84(kE0 + x, kN0 + y, kZone);
  return roadcross::testing::osm_node(id, ll.lat_deg, ll.lon_deg, tags);
}

}  // namespace

TEST(SightBuild, BuildingsFromOsmReachTheDatabase) {
  TempDir dir;
  namespace t = roadcross::testing;
  // The L-shaped road of LShapedRoadWithABuildingInTheCorner; the building from OSM with
  // building:levels=3 (9 m) and a building=roof that must not count.
  const std::string osm =
      t::osm_document(node_at(1, -200, 0) + node_at(2, 0, 0) + node_at(3, 0, 200) +
                      node_at(11, -100, 10) + node_at(12, -10, 10) + node_at(13, -10, 100) +
                      node_at(14, -100, 100) + node_at(21, -40, -10) + node_at(22, 40, -10) +
                      node_at(23, 40, -60) + t::osm_way(1, "1 2 3", "highway=residential") +
                      t::osm_way(10, "11 12 13 14 11", "building=yes;building:levels=3") +
                      t::osm_way(20, "21 22 23 21", "building=roof"));
  rp::BuildOptions options;
  options.osm_path = dir.write("l.osm", osm);
  options.output_path = dir.file("l.gpkg");
  // 400 m in 20 segments (the lat/lon rounding makes it a few mm longer than 400).
  options.parameters.segments.max_segment_length_m = 20.01;
  const rp::BuildSummary summary = rp::run_build(options);
  EXPECT_THAT(
      summary.notes,
      ::testing::Contains(::testing::HasSubstr("sight obstacles: 1 buildings, 0 walls, 0 fences")));
  roadcross::sqlite::Database db(options.output_path, SQLITE_OPEN_READONLY);
  auto q = db.prepare(
      "SELECT sight_forward_m, sight_backward_m, sight_min_m, required_sight_m, reasons "
      "FROM segments JOIN rtree_segments_geom ON id = fid "
      "WHERE (minx + maxx) / 2 BETWEEN ?1 - 1 AND ?1 + 1 AND maxy < ?2");
  q.bind(1, kE0 - 30.0);
  q.bind(2, kN0 + 1.0);
  ASSERT_TRUE(q.step());
  // The context's width for an untagged residential road is 2 lanes x 3.0 m = 6 m, as in the
  // hand computation.
  EXPECT_NEAR(q.column_double(0), 43.5, 0.2);
  EXPECT_DOUBLE_EQ(q.column_double(1), 300.0);
  EXPECT_NEAR(q.column_double(2), 43.5, 0.2);
  EXPECT_GT(q.column_double(3), 43.5);
  EXPECT_THAT(q.column_text(4), ::testing::HasSubstr("LIMITED_VISIBILITY"));
  q.reset();

  // The runtime: by default LIMITED_VISIBILITY makes the place unsuitable whatever its score;
  // 150 m back along the straight leg (sight 300 m both ways) the same road is suitable.
  const auto assess = [&](const std::string& path, double x) {
    auto map = roadcross::Map::open(path);
    EXPECT_TRUE(map.ok()) << map.status.message;
    auto a = map.value->assess(roadcross::Position::utm(kE0 + x, kN0 - 3.0));
    EXPECT_TRUE(a.ok()) << a.status.message;
    return *a.value;
  };
  const roadcross::Assessment near_corner = assess(options.output_path, -30.0);
  EXPECT_FALSE(near_corner.suitable);
  // ... and for that reason alone: its score and context are good enough.
  EXPECT_THAT(near_corner.reasons, ::testing::Not(::testing::Contains("LOW_SCORE")));
  EXPECT_THAT(near_corner.reasons, ::testing::Contains("LIMITED_VISIBILITY"));
  EXPECT_TRUE(assess(options.output_path, -150.0).suitable);
  ASSERT_TRUE(near_corner.sight_min_m && near_corner.required_sight_m);
  EXPECT_NEAR(*near_corner.sight_forward_m, 43.5, 0.2);
  EXPECT_NEAR(*near_corner.sight_min_m, 43.5, 0.2);
  EXPECT_DOUBLE_EQ(*near_corner.sight_backward_m, 300.0);
  EXPECT_GT(*near_corner.required_sight_m, 43.5);

  // A schema version 1 DB (no sight columns) is still read: the sight is simply unknown.
  const std::string v1 = dir.file("v1.gpkg");
  ASSERT_EQ(std::system(("cp '" + options.output_path + "' '" + v1 + "'").c_str()), 0);
  {
    roadcross::sqlite::Database w(v1, SQLITE_OPEN_READWRITE);
    for (const char* column :
         {"sight_forward_m", "sight_backward_m", "sight_min_m", "required_sight_m"}) {
      w.exec(std::string("ALTER TABLE segments DROP COLUMN ") + column);
    }
    w.exec("UPDATE roadcross_metadata SET value = '1' WHERE key = 'schema_version'");
  }
  const roadcross::Assessment old = assess(v1, -30.0);
  EXPECT_FALSE(old.sight_min_m.has_value());
  EXPECT_EQ(old.score, near_corner.score);

  // Cost mode: only a rank penalty (4), so the score drops by 4 and the runtime judges the
  // score alone.
  options.parameters.sight.limited_visibility_unsuitable = 0.0;
  options.output_path = dir.file("cost.gpkg");
  rp::run_build(options);
  const roadcross::Assessment cost = assess(options.output_path, -30.0);
  EXPECT_THAT(cost.reasons, ::testing::Contains("LIMITED_VISIBILITY"));
  EXPECT_EQ(*cost.score, *near_corner.score - 4);
  EXPECT_EQ(cost.suitable, *cost.score + cost.context_score.value_or(0) >= 20);

  // The stage switched off: the columns are NULL and no segment is limited.
  options.parameters.sight.enabled = 0.0;
  options.output_path = dir.file("off.gpkg");
  rp::run_build(options);
  roadcross::sqlite::Database off(options.output_path, SQLITE_OPEN_READONLY);
  auto n = off.prepare(
      "SELECT count(*) FROM segments WHERE sight_min_m IS NOT NULL OR reasons LIKE "
      "'%LIMITED_VISIBILITY%'");
  ASSERT_TRUE(n.step());
  EXPECT_EQ(n.column_int64(0), 0);
}

TEST(SightObstacles, ReaderKeepsEachWaysChainsOfNearEdgesAsRuns) {
  // Road 1 spans the box x -200..0, y 0..200 (offsets from (kE0, kN0)); edges are kept within
  // 100 m of it, nodes within 1 100 m. Ways in id order:
  //  3  a fence of 65 edges (nodes 100-165, x = -200, -197, ..., -5 at y = -5): runs of 64 and
  //     1 edges, 69 slots (the second run repeats vertex 64 after its own header) against the
  //     way's 67: the reader lays the ways out after 2 slots of room for that cut; slots 0-68;
  //  5  a wall 61-62-63-64 whose middle edge (x = 500) is beyond 100 m: two chains, 6 slots
  //     against the way's own 5 (header + 4 references) and no room left before the next way,
  //     so its runs go after all the others;
  // 10  a building ring 11-12-13-14-11, band 2-9 m: 4 edges, slots 69-74;
  // 30  a wall 31-32-(33 not in the file)-34: only 31-32 is an edge, slots 75-77;
  // 40  a fence 5 km away: nothing;
  // 50  a wall 51-(52 3 km away)-53-54: only 53-54, slots 78-80;
  // then wall 5's runs, slots 81-83 and 84-86.
  TempDir dir;
  namespace t = roadcross::testing;
  std::string fence_nodes, fence_refs;
  for (int j = 0; j <= 65; ++j) {
    fence_nodes += node_at(100 + j, -200 + 3 * j, -5);
    fence_refs += std::to_string(100 + j) + " ";
  }
  const std::string osm = t::osm_document(
      node_at(1, -200, 0) + node_at(2, 0, 0) + node_at(3, 0, 200) + node_at(11, -100, 10) +
      node_at(12, -10, 10) + node_at(13, -10, 100) + node_at(14, -100, 100) + node_at(31, 20, 20) +
      node_at(32, 40, 20) + node_at(34, 60, 20) + node_at(41, 5000, 0) + node_at(42, 5010, 0) +
      node_at(51, 20, -20) + node_at(52, 3000, -20) + node_at(53, 30, -30) + node_at(54, 40, -30) +
      node_at(61, 50, 50) + node_at(62, 500, 50) + node_at(63, 500, 60) + node_at(64, 50, 60) +
      fence_nodes + t::osm_way(1, "1 2 3", "highway=residential") +
      t::osm_way(3, fence_refs, "barrier=fence") + t::osm_way(5, "61 62 63 64", "barrier=wall") +
      t::osm_way(10, "11 12 13 14 11", "building=yes;height=9;min_height=2") +
      t::osm_way(30, "31 32 33 34", "barrier=wall") + t::osm_way(40, "41 42", "barrier=fence") +
      t::osm_way(50, "51 52 53 54", "barrier=wall"));
  const rp::SightParameters p;
  rp::ObstacleReader reader(p);
  rp::Progress progress(false);
  rp::read_road_network(dir.write("o.osm", osm), progress, &reader);
  const rp::Obstacles o = reader.take_edges(kZone, {kE0 - 200, kN0}, {kE0, kN0 + 200}, 100.0);
  EXPECT_EQ(o.report.buildings, 1u);
  EXPECT_EQ(o.report.walls, 3u);
  EXPECT_EQ(o.report.fences, 2u);
  EXPECT_EQ(o.report.edges, 73u);
  ASSERT_EQ(o.edges.slots(), 87u);
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < o.edges.slots(); ++i) {
    if (o.edges.is_edge(i)) ids.push_back(i);
  }
  std::vector<std::size_t> want;
  for (std::size_t i = 1; i <= 64; ++i) want.push_back(i);
  for (std::size_t i : {67, 70, 71, 72, 73, 76, 79, 82, 85}) want.push_back(i);
  EXPECT_EQ(ids, want);
  // The node positions went through 7 decimals of a degree: within 2 cm.
  const auto expect_at = [](const PlanePoint& q, double x, double y) {
    EXPECT_NEAR(q.x, kE0 + x, 0.02);
    EXPECT_NEAR(q.y, kN0 + y, 0.02);
  };
  expect_at(o.edges.a(1), -200, -5);
  expect_at(o.edges.a(64), -11, -5);
  expect_at(o.edges.b(64), -8, -5);
  expect_at(o.edges.a(67), -8, -5);
  expect_at(o.edges.b(67), -5, -5);
  EXPECT_EQ(o.edges.top_m(64), 1.5f);  // fence_height_m
  EXPECT_EQ(o.edges.top_m(67), 1.5f);
  expect_at(o.edges.a(70), -100, 10);
  expect_at(o.edges.b(70), -10, 10);
  expect_at(o.edges.a(73), -100, 100);
  EXPECT_EQ(o.edges.b(73).x, o.edges.a(70).x);  // the ring's first node, projected once
  EXPECT_EQ(o.edges.b(73).y, o.edges.a(70).y);
  EXPECT_EQ(o.edges.bottom_m(72), 2.0f);
  EXPECT_EQ(o.edges.top_m(72), 9.0f);
  expect_at(o.edges.a(76), 20, 20);
  expect_at(o.edges.b(76), 40, 20);
  EXPECT_EQ(o.edges.bottom_m(76), 0.0f);
  EXPECT_EQ(o.edges.top_m(76), 2.0f);  // wall_height_m
  expect_at(o.edges.a(79), 30, -30);
  expect_at(o.edges.b(79), 40, -30);
  expect_at(o.edges.a(82), 50, 50);
  expect_at(o.edges.b(82), 500, 50);
  expect_at(o.edges.a(85), 500, 60);
  expect_at(o.edges.b(85), 50, 60);
  EXPECT_EQ(o.edges.top_m(85), 2.0f);
}

TEST(SightObstacles, AnEmptyRoadBoxKeepsNoEdgeAndNeedsNoFrame) {
  // take_edges with the box of no road (min above max, as the build's fold starts): no node is
  // kept, and no fixed-point frame is made for the inverted box.
  TempDir dir;
  namespace t = roadcross::testing;
  const std::string osm = t::osm_document(
      node_at(1, -200, 0) + node_at(2, 0, 0) + node_at(11, -100, 10) + node_at(12, -10, 10) +
      node_at(13, -10, 100) + t::osm_way(1, "1 2", "highway=residential") +
      t::osm_way(10, "11 12 13 11", "building=yes"));
  const rp::SightParameters p;
  rp::ObstacleReader reader(p);
  rp::Progress progress(false);
  rp::read_road_network(dir.write("o.osm", osm), progress, &reader);
  const rp::Obstacles o = reader.take_edges(kZone, {1e300, 1e300}, {-1e300, -1e300}, 100.0);
  EXPECT_EQ(o.report.buildings, 1u);
  EXPECT_EQ(o.report.edges, 0u);
  EXPECT_EQ(o.edges.slots(), 0u);
}
