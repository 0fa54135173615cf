// Geometry cost: circumradius, curvature on drawn arcs, junction distance along the road,
// the junction's level-5 reach, the curvature window (through junctions), the elevation cost's
// scale and window, class cost, rank. Expected values are computed by hand in comments.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/geometry/curvature.hpp"
#include "roadcross/preprocess/geometry/geometry_cost.hpp"
#include "roadcross/preprocess/graph/strokes.hpp"
#include "roadcross/preprocess/parameters.hpp"
#include "roadcross/preprocess/rank.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"

namespace rp = roadcross::preprocess;
using rp::PlanePoint;

namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- A tiny graph builder in plane coordinates (no OSM, no projection). ----------------------

struct GraphBuilder {
  rp::RoadGraph graph;
  /// Adds a piece from node `from` to `to` along `points`, cut into segments of <= max_m, of
  /// OSM way `way_id` (0: a way of its own, id = piece index + 1000) named `name`.
  void add_piece(std::int64_t from, std::int64_t to, std::vector<PlanePoint> points,
                 const std::string& highway = "residential", double max_m = 10.0,
                 std::int64_t way_id = 0, const std::string& name = "") {
    rp::RoadPiece piece;
    piece.from_node_id = from;
    piece.to_node_id = to;
    piece.osm_way_id = way_id != 0 ? way_id : static_cast<std::int64_t>(graph.pieces.size()) + 1000;
    if (!name.empty()) piece.name = graph.text.intern_text(name);
    piece.highway = graph.text.intern_text(highway);
    piece.points = points;
    piece.length_m = rp::polyline_length_m(points);
    piece.first_segment = graph.segments.size();
    // Cut into equal parts along the polyline (same rule as the segmenter).
    const auto count =
        static_cast<std::size_t>(std::max(1.0, std::ceil(piece.length_m / max_m - 1e-9)));
    piece.segment_count = count;
    std::vector<double> s(points.size(), 0.0);
    for (std::size_t i = 1; i < points.size(); ++i)
      s[i] = s[i - 1] + std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
    auto at = [&](double d) {
      std::size_t j = 1;
      while (j + 1 < points.size() && s[j] < d) ++j;
      const double t = (d - s[j - 1]) / (s[j] - s[j - 1]);
      return PlanePoint{points[j - 1].x + t * (points[j].x - points[j - 1].x),
                        points[j - 1].y + t * (points[j].y - points[j - 1].y)};
    };
    for (std::size_t k = 0; k < count; ++k) {
      const double n = static_cast<double>(count);
      const double a = piece.length_m * static_cast<double>(k) / n,
                   b = piece.length_m * static_cast<double>(k + 1) / n;
      rp::Segment seg;
      seg.piece_index = static_cast<std::uint32_t>(graph.pieces.size());
      std::vector<PlanePoint>& line = graph.segment_points;
      // As the segmenter stores them: a segment starts on the point the previous segment of
      // its piece ends on (RoadGraph::line derives the point count from that).
      if (k == 0) line.push_back(at(a));
      seg.first_point = static_cast<std::uint32_t>(line.size() - 1);
      for (std::size_t i = 1; i + 1 < points.size(); ++i) {
        if (s[i] > a && s[i] < b) line.push_back(points[i]);
      }
      line.push_back(k + 1 == count ? points.back() : at(b));
      graph.segments.push_back(seg);
    }
    ++graph.degree[from];
    ++graph.degree[to];
    graph.pieces.push_back(piece);
  }
};

std::vector<PlanePoint> straight(PlanePoint a, PlanePoint b) {
  return {a, b};
}

/// Vertices on a circle of `radius_m` around the origin, `spacing_m` apart along the arc,
/// spanning `angle_rad`, starting at angle `start_rad`.
std::vector<PlanePoint> arc(double radius_m, double spacing_m, double angle_rad,
                            double start_rad = 0.0) {
  std::vector<PlanePoint> out;
  const int steps = static_cast<int>(std::round(angle_rad * radius_m / spacing_m));
  for (int i = 0; i <= steps; ++i) {
    const double t = start_rad + angle_rad * i / steps;
    out.push_back({radius_m * std::cos(t), radius_m * std::sin(t)});
  }
  return out;
}

// ---- Circumradius. ---------------------------------------------------------------------------

TEST(Circumradius, KnownTriangles) {
  // Right triangle 3-4-5: the hypotenuse is a diameter, r = 2.5.
  EXPECT_NEAR(rp::circumradius_m({0, 0}, {3, 0}, {3, 4}, 1e4), 2.5, 1e-12);
  // Equilateral triangle of side a: r = a / sqrt(3).
  EXPECT_NEAR(rp::circumradius_m({0, 0}, {10, 0}, {5, 10 * std::sqrt(3.0) / 2}, 1e4),
              10 / std::sqrt(3.0), 1e-9);
  // Any three points of a circle of radius 50.
  EXPECT_NEAR(rp::circumradius_m({50, 0}, {0, 50}, {-50 * std::cos(0.3), -50 * std::sin(0.3)}, 1e4),
              50, 1e-9);
  // Collinear and degenerate: the straight radius.
  EXPECT_EQ(rp::circumradius_m({0, 0}, {5, 0}, {10, 0}, 10000), 10000);
  EXPECT_EQ(rp::circumradius_m({0, 0}, {0, 0}, {10, 0}, 10000), 10000);
  EXPECT_EQ(rp::circumradius_m({1, 1}, {1, 1}, {1, 1}, 10000), 10000);
  // Nearly straight: capped at the straight radius.
  EXPECT_EQ(rp::circumradius_m({0, 0}, {500, 0.001}, {1000, 0}, 10000), 10000);
}

TEST(RadiusProfile, VerticesCarryTheBendInsertedPointsAreStraight) {
  // A 50 m edge east, then 7.07 m north-east (a 45 degree turn at (50, 0)).
  const rp::RadiusProfile out = rp::radius_profile({{0, 0}, {50, 0}, {55, 5}}, {}, 20.0);
  // 50 m edge -> 3 parts of 16.67 m; the 7.07 m edge is not split.
  ASSERT_EQ(out.position_m.size(), 5u);
  EXPECT_NEAR(out.position_m[1], 50.0 / 3, 1e-12);
  EXPECT_NEAR(out.position_m[3], 50.0, 1e-12);
  EXPECT_NEAR(out.position_m[4], 50.0 + std::sqrt(50.0), 1e-12);
  // Open ends and inserted points: straight.
  EXPECT_EQ(out.radius_m[0], 10000);
  EXPECT_EQ(out.radius_m[1], 10000);
  EXPECT_EQ(out.radius_m[2], 10000);
  EXPECT_EQ(out.radius_m[4], 10000);
  // At (50, 0): back arm 50 m (at the cap) reaches (0, 0); the forward arm (10 m baseline) is
  // cut at the line's end (55, 5). Angle 135 degrees at the vertex:
  //   r = |AC| / (2 sin 135) = sqrt(55^2 + 5^2) / sqrt(2) = 39.051 m.
  EXPECT_NEAR(out.radius_m[3], std::sqrt(55.0 * 55 + 25) / std::sqrt(2.0), 1e-9);
}

// ---- Curvature on drawn arcs: radius_m within 10 % whatever the vertex spacing. --------------

class ArcRadius : public ::testing::TestWithParam<std::tuple<double, double>> {};

TEST_P(ArcRadius, SegmentsOnTheArcGetItsRadius) {
  const auto [radius, spacing] = GetParam();
  GraphBuilder b;
  // Three quarters of a circle, as one piece between two dead ends.
  b.add_piece(1, 2, arc(radius, spacing, 1.5 * kPi));
  rp::GeometryParameters p;
  rp::compute_geometry_costs(b.graph, p);
  int checked = 0;
  for (const rp::Segment& s : b.graph.segments) {
    ASSERT_TRUE(s.radius_m.has_value());
    // The segments at the two dead ends see only half a triangle; the rest must be within 10 %.
    const double from_start = b.graph.offset_in_piece_m(s),
                 to_end = b.graph.pieces[0].length_m - from_start - b.graph.length_m(s);
    if (from_start < spacing + p.curvature_baseline_m || to_end < spacing + p.curvature_baseline_m)
      continue;
    EXPECT_NEAR(*s.radius_m, radius, 0.10 * radius) << "segment at " << from_start << " m";
    ++checked;
  }
  EXPECT_GE(checked, 5);
}

INSTANTIATE_TEST_SUITE_P(RadiiAndSpacings, ArcRadius,
                         ::testing::Combine(::testing::Values(30.0, 50.0, 100.0, 200.0),
                                            ::testing::Values(2.0, 5.0, 15.0)));

// A vertex's triangle reaches to its real neighbours, clamped to [baseline 10, max arm 50] m.
// On a circle of radius R with vertices d apart, half the deflection at a vertex is
// asin(d / 2R), and two equal arms L give the circumradius L / (2 sin(deflection / 2)).

TEST(Curvature, GentleCurveDrawnWithSparseVerticesIsNotASharpBend) {
  // R = 250 m, d = 40 m: arms 40 m, r = 40 / (2 * 40/500) = 250 exactly. (Resampling first and
  // using the 20 m neighbours read 20 / 0.16 = 125 m.) d = 60 m: arms capped at 50 m,
  // r = 50 / (2 * 60/500) = 208.33 m: level 1, no SHARP_BEND (resampled: 20 / 0.24 = 83 m).
  for (const auto& [spacing, expected] : {std::pair{40.0, 250.0}, std::pair{60.0, 208.333}}) {
    // Vertices on the circle with chords of exactly `spacing`: 2 asin(d / 2R) apart.
    const double step_rad = 2 * std::asin(spacing / 500);
    std::vector<PlanePoint> line;
    for (int i = 0; i <= 8; ++i)
      line.push_back({250 * std::cos(i * step_rad), 250 * std::sin(i * step_rad)});
    GraphBuilder b;
    b.add_piece(1, 2, line);
    rp::compute_geometry_costs(b.graph, {});
    int at_vertices = 0;
    for (const rp::Segment& s : b.graph.segments) {
      // Samples between vertices are on a straight edge; only a vertex's neighbourhood bends.
      if (*s.radius_m < 10000) {
        EXPECT_NEAR(*s.radius_m, expected, 0.01 * expected) << spacing;
        ++at_vertices;
      }
      EXPECT_LE(*s.curvature_level, 1) << spacing;
      EXPECT_TRUE(s.reasons.empty()) << spacing;
    }
    EXPECT_GE(at_vertices, static_cast<int>(line.size()) - 2) << spacing;
  }
}

TEST(Curvature, SingleVertexCornerBetweenLongEdgesIsACorner) {
  // 200 m edges meeting at one vertex: the arms are capped at 50 m, so a 90 degree corner reads
  // 50 / (2 sin 45) = 35.36 m (level 4, SHARP_BEND) and a 30 degree kink 50 / (2 sin 15) =
  // 96.59 m (level 2), not the 141 m / 386 m of the circle through the far vertices.
  GraphBuilder b;
  b.add_piece(1, 2, {{-200, 0}, {0, 0}, {0, 200}});
  const double t = 30 * kPi / 180;
  b.add_piece(3, 4, {{-200, 1000}, {0, 1000}, {200 * std::cos(t), 1000 + 200 * std::sin(t)}});
  rp::compute_geometry_costs(b.graph, {});
  const auto min_radius = [&](std::size_t piece) {
    double r = 1e9;
    for (const rp::Segment& s : b.graph.segments) {
      if (s.piece_index == piece) r = std::min<double>(r, *s.radius_m);
    }
    return r;
  };
  EXPECT_NEAR(min_radius(0), 50 / (2 * std::sin(kPi / 4)), 1e-6);
  EXPECT_NEAR(min_radius(1), 50 / (2 * std::sin(kPi / 12)), 1e-6);
  const rp::Segment& at_corner = b.graph.segments[19];  // ends at the corner vertex (200 m)
  EXPECT_EQ(*at_corner.curvature_level, 4);
  EXPECT_EQ(at_corner.reasons.list(), std::vector<std::string>{"SHARP_BEND"});
}

TEST(Curvature, StraightRoadIsStraightLevelZeroCostZero) {
  GraphBuilder b;
  b.add_piece(1, 2, {{0, 0}, {100, 0}, {200, 0}, {300, 0}});
  rp::compute_geometry_costs(b.graph, {});
  for (const rp::Segment& s : b.graph.segments) {
    EXPECT_EQ(*s.radius_m, 10000);
    EXPECT_EQ(*s.curvature_level, 0);
    EXPECT_EQ(*s.curvature_cost, 0);                  // floor(0.75)
    EXPECT_FALSE(s.junction_distance_m.has_value());  // no junction anywhere
    EXPECT_TRUE(s.reasons.empty());
  }
}

TEST(Curvature, LevelsFollowTheRadiusLimits) {
  const rp::GeometryParameters p;
  EXPECT_EQ(rp::curvature_level(39.9, false, p), 4);
  EXPECT_EQ(rp::curvature_level(40.0, false, p), 3);
  EXPECT_EQ(rp::curvature_level(89.9, false, p), 3);
  EXPECT_EQ(rp::curvature_level(149.9, false, p), 2);
  EXPECT_EQ(rp::curvature_level(219.9, false, p), 1);
  EXPECT_EQ(rp::curvature_level(220.0, false, p), 0);
  EXPECT_EQ(rp::curvature_level(10000, true, p), 5);
}

TEST(Curvature, SplittingARoadIntoTwoWaysChangesNothing) {
  // The same 50 m-radius S-bend, once as one piece and once as two pieces joined at a
  // degree-2 node in the middle of the bend.
  std::vector<PlanePoint> line = {{-100, 0}};
  for (const PlanePoint& q : arc(50, 5, kPi / 2, -kPi / 2)) line.push_back({q.x, q.y + 50});
  line.push_back({50, 150});
  GraphBuilder one, two;
  one.add_piece(1, 2, line);
  const std::size_t middle = line.size() / 2;
  two.add_piece(
      1, 3, std::vector<PlanePoint>(line.begin(), line.begin() + static_cast<long>(middle) + 1));
  two.add_piece(3, 2,
                std::vector<PlanePoint>(line.begin() + static_cast<long>(middle), line.end()));
  rp::compute_geometry_costs(one.graph, {});
  rp::compute_geometry_costs(two.graph, {});
  // Compare the cost profile along the road at the same positions (segment boundaries differ
  // slightly because the pieces are cut separately; sample every segment midpoint of `one`).
  auto profile = [](const rp::RoadGraph& g) {
    std::vector<std::tuple<double, double, int, int>> out;  // position, radius, level, cost
    double base = 0;
    for (const rp::RoadPiece& piece : g.pieces) {
      for (std::size_t k = 0; k < piece.segment_count; ++k) {
        const rp::Segment& s = g.segments[piece.first_segment + k];
        out.emplace_back(base + g.offset_in_piece_m(s) + g.length_m(s) / 2, *s.radius_m,
                         *s.curvature_level, *s.curvature_cost);
      }
      base += piece.length_m;
    }
    return out;
  };
  const auto a = profile(one.graph), b = profile(two.graph);
  for (const auto& [pos, radius, level, cost] : a) {
    // The segment of `two` at the same position.
    const auto it = std::min_element(b.begin(), b.end(), [&](const auto& x, const auto& y) {
      return std::abs(std::get<0>(x) - pos) < std::abs(std::get<0>(y) - pos);
    });
    if (std::abs(std::get<0>(*it) - pos) > 1.0) continue;  // boundaries too different to compare
    EXPECT_NEAR(std::get<1>(*it), radius, 0.05 * radius) << "at " << pos;
    EXPECT_EQ(std::get<3>(*it), cost) << "at " << pos;
  }
  // The join node is not a junction: nobody is NEAR_JUNCTION, nobody has level 5.
  for (const rp::Segment& s : two.graph.segments) {
    EXPECT_NE(*s.curvature_level, 5);
    EXPECT_FALSE(s.junction_distance_m.has_value());
  }
}

// ---- Junction distance along the road. ---------------------------------------------------------

TEST(Junctions, TJunctionDistancesAlongTheRoad) {
  // Main road 1 -(100 m)- 2 -(60 m)- 3 along the x axis; side road 2 -(40 m)- 4 north.
  // Node 2 has degree 3. With 10 m segments, the k-th segment of piece 1-2 (from node 1) has its
  // midpoint at 5 + 10 k m from node 1, i.e. 95 - 10 k m from the junction.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {100, 0}));
  b.add_piece(2, 3, straight({100, 0}, {160, 0}));
  b.add_piece(2, 4, straight({100, 0}, {100, 40}));
  rp::compute_geometry_costs(b.graph, {});
  const auto& seg = b.graph.segments;
  EXPECT_NEAR(*seg[0].junction_distance_m, 95.0, 1e-9);
  EXPECT_NEAR(*seg[9].junction_distance_m, 5.0, 1e-9);
  EXPECT_NEAR(*seg[10].junction_distance_m, 5.0, 1e-9);   // first of 2-3
  EXPECT_NEAR(*seg[15].junction_distance_m, 55.0, 1e-9);  // last of 2-3
  EXPECT_NEAR(*seg[19].junction_distance_m, 35.0, 1e-9);  // last of 2-4
  // NEAR_JUNCTION below 15 m: midpoints at 5 m only (the next ones are at 15 m).
  auto near = [](const rp::Segment& s) { return s.reasons.contains("NEAR_JUNCTION"); };
  EXPECT_TRUE(near(seg[9]));
  EXPECT_FALSE(near(seg[8]));
  EXPECT_TRUE(near(seg[10]));
  EXPECT_FALSE(near(seg[11]));
  // Level 5 on the road within geometry.junction_extent_m (20 m) of the junction: segments
  // whose nearer end is < 20 m away. On 1-2, segment 9 (90..100) touches it, segment 8
  // (80..90) comes within 10 m, segment 7 (70..80) only within 20 m: level 0.
  EXPECT_EQ(*seg[9].curvature_level, 5);
  EXPECT_EQ(*seg[8].curvature_level, 5);
  EXPECT_EQ(*seg[7].curvature_level, 0);
  EXPECT_EQ(*seg[10].curvature_level, 5);
  EXPECT_EQ(*seg[11].curvature_level, 5);
  EXPECT_EQ(*seg[12].curvature_level, 0);
  EXPECT_EQ(*seg[16].curvature_level, 5);  // first of 2-4
  EXPECT_EQ(*seg[17].curvature_level, 5);
  EXPECT_EQ(*seg[18].curvature_level, 0);
}

TEST(Junctions, LevelFiveReachIsTheSameForAnySegmentLength) {
  // A T: main road 1 -(200 m)- 2 -(200 m)- 3 along x, side road 2 -(100 m)- 4 north. With
  // segments of 5, 10 and 20 m (all divide 20), exactly the segments covering the 20 m next to
  // the junction have a nearer end < 20 m from it: 20 m of level 5 on each of the three roads,
  // 60 m in all, whatever the segment length. (Before, only the segments touching the junction
  // were level 5: 5, 10 or 20 m a road.)
  for (const double length_m : {5.0, 10.0, 20.0}) {
    GraphBuilder b;
    b.add_piece(1, 2, straight({0, 0}, {200, 0}), "residential", length_m);
    b.add_piece(2, 3, straight({200, 0}, {400, 0}), "residential", length_m);
    b.add_piece(2, 4, straight({200, 0}, {200, 100}), "residential", length_m);
    rp::compute_geometry_costs(b.graph, {});
    std::array<double, 3> level5_m{};
    for (const rp::Segment& s : b.graph.segments) {
      if (*s.curvature_level == 5) level5_m[s.piece_index] += b.graph.length_m(s);
    }
    for (std::size_t piece = 0; piece < 3; ++piece)
      EXPECT_NEAR(level5_m[piece], 20.0, 1e-9) << length_m << " m segments, piece " << piece;
    // The level-5 stretch ends 20 m from the junction: the segment starting there is level 0.
    const rp::RoadPiece& main = b.graph.pieces[0];
    const std::size_t beyond = main.first_segment + main.segment_count - 1 -
                               static_cast<std::size_t>(std::lround(20.0 / length_m));
    EXPECT_EQ(*b.graph.segments[beyond].curvature_level, 0) << length_m;
  }
  // The reach is a parameter: 0 keeps only the segments touching the junction.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {200, 0}));
  b.add_piece(2, 3, straight({200, 0}, {400, 0}));
  b.add_piece(2, 4, straight({200, 0}, {200, 100}));
  rp::GeometryParameters touching_only;
  touching_only.junction_extent_m = 0;
  rp::compute_geometry_costs(b.graph, touching_only);
  EXPECT_EQ(*b.graph.segments[19].curvature_level, 5);
  EXPECT_EQ(*b.graph.segments[18].curvature_level, 0);
}

TEST(Junctions, NearestJunctionIsFoundThroughOtherPieces) {
  // 1 -(50)- 2 -(50)- 3 where 2 is degree 2 (ways joined) and 3 is an X junction with 5, 6, 7.
  // The first segment of 1-2 (midpoint 5 m from node 1) is 95 m from the junction at node 3.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {50, 0}));
  b.add_piece(2, 3, straight({50, 0}, {100, 0}));
  b.add_piece(3, 5, straight({100, 0}, {150, 0}));
  b.add_piece(3, 6, straight({100, 0}, {100, 50}));
  b.add_piece(3, 7, straight({100, 0}, {100, -50}));
  rp::compute_geometry_costs(b.graph, {});
  EXPECT_EQ(b.graph.degree[3], 4);
  EXPECT_NEAR(*b.graph.segments[0].junction_distance_m, 95.0, 1e-9);
}

// ---- The curvature window. -------------------------------------------------------------------

TEST(CurvatureWindow, HandComputedExample) {
  // A 400 m straight road of 40 segments of 10 m, no junction. Segment 20 (200..210 m) is given
  // level 4 (weight 20), all others level 0 (weight 0.75).
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {400, 0}));
  rp::GeometryParameters p;
  rp::compute_geometry_costs(b.graph, p);
  for (rp::Segment& s : b.graph.segments) s.curvature_level = 0;
  b.graph.segments[20].curvature_level = 4;
  const std::vector<rp::Stroke> strokes = rp::build_strokes(b.graph);
  ASSERT_EQ(strokes.size(), 1u);
  rp::assign_curvature_costs(b.graph, strokes[0], p);
  const auto cost = [&](std::size_t i) { return *b.graph.segments[i].curvature_cost; };
  // Segment 20, window 105..305: itself 10 m x3 at 20, 190 m at 0.75:
  //   (600 + 142.5) / (30 + 190) = 3.375 -> 3.
  EXPECT_EQ(cost(20), 3);
  // Segment 21, window 115..315: segment 20 (10 m at 20), itself x3 at 0.75, 180 m at 0.75:
  //   (200 + 22.5 + 135) / 220 = 1.625 -> 1.
  EXPECT_EQ(cost(21), 1);
  // Segment 11, window 15..215: segment 20 fully inside: same as 21 -> 1.
  EXPECT_EQ(cost(11), 1);
  // Segment 10, window 5..205: 5 m of segment 20 at 20, itself 30 at 0.75, 185 m at 0.75:
  //   (100 + 22.5 + 138.75) / 220 = 1.1875 -> 1.
  EXPECT_EQ(cost(10), 1);
  // Segment 9, window -5..195 (clipped at the road's start to 0..195): does not reach 200.
  EXPECT_EQ(cost(9), 0);
  // Segment 0, window 0..105 (clipped): (10 * 0.75 * 3 + 95 * 0.75) / 125 = 0.75 -> 0.
  EXPECT_EQ(cost(0), 0);
  // With level 5 (weight 30) on segment 20: (900 + 142.5) / 220 = 4.74 -> 4.
  b.graph.segments[20].curvature_level = 5;
  rp::assign_curvature_costs(b.graph, strokes[0], p);
  EXPECT_EQ(cost(20), 4);
  // Every segment at level 5: 30 -> clamped to 14.
  for (rp::Segment& s : b.graph.segments) s.curvature_level = 5;
  rp::assign_curvature_costs(b.graph, strokes[0], p);
  EXPECT_EQ(cost(0), 14);
  // Every segment at level 1 (weight 3): exactly 3, not floored to 2 by rounding.
  for (rp::Segment& s : b.graph.segments) s.curvature_level = 1;
  rp::assign_curvature_costs(b.graph, strokes[0], p);
  EXPECT_EQ(cost(17), 3);
}

// ---- The curvature window through junctions. ----------------------------------------------

/// Main road 1 -(200 m)- 2 -(200 m)- 3 along x and side road(s) at node 2, 10 m segments; the
/// curvature levels are then set by hand: all 0 (weight 0.75), except level 4 (weight 20) on
/// the segment 30..40 m beyond the junction on the through road (`bend_on_through`) or on the
/// side road (else). Returns the curvature cost of segment 19 of the main road (190..200 m, the
/// one touching the junction, midpoint 195 m), with the window through junctions on or off.
int cost_before_junction(GraphBuilder& b, bool bend_on_through, bool through) {
  rp::GeometryParameters p;
  p.window_through_junctions = through ? 1 : 0;
  rp::compute_geometry_costs(b.graph, p);
  for (rp::Segment& s : b.graph.segments) s.curvature_level = 0;
  const rp::RoadPiece& bent = b.graph.pieces[bend_on_through ? 1 : 2];
  b.graph.segments[bent.first_segment + 3].curvature_level = 4;  // 30..40 m from node 2
  const rp::Incidences nodes(b.graph);
  for (const rp::Stroke& stroke : rp::build_strokes(b.graph))
    rp::assign_curvature_costs(b.graph, stroke, p, through ? &nodes : nullptr);
  return *b.graph.segments[19].curvature_cost;
}

// Segment 19's window is 95..295 m. Through the junction on the through road: itself 10 m x3
// at 0.75, 180 m at 0.75 and the bend's 10 m at 20:
//   (22.5 + 135 + 200) / (30 + 190) = 1.625 -> 1.
// Ending at the junction (95..200 m): everything at 0.75 -> 0.

TEST(CurvatureWindow, GoesOnThroughAnXJunctionAlongTheWay) {
  // Way 100 runs 1 -> 2 -> 3 through the junction, way 200 crosses it 4 -> 2 -> 5 (an X).
  const auto x_junction = [] {
    GraphBuilder b;
    b.add_piece(1, 2, straight({0, 0}, {200, 0}), "residential", 10.0, 100);
    b.add_piece(2, 3, straight({200, 0}, {400, 0}), "residential", 10.0, 100);
    b.add_piece(4, 2, straight({200, -100}, {200, 0}), "residential", 10.0, 200);
    b.add_piece(2, 5, straight({200, 0}, {200, 100}), "residential", 10.0, 200);
    return b;
  };
  GraphBuilder through = x_junction(), ends = x_junction();
  EXPECT_EQ(cost_before_junction(through, true, true), 1);
  EXPECT_EQ(cost_before_junction(ends, true, false), 0);
  // The crossing way's bend 30..40 m up piece 4-2 (index 2 here: 30..40 m from node 4, i.e.
  // 60..70 m from the junction) is never seen from the main road: 0 with the window through.
  GraphBuilder side = x_junction();
  EXPECT_EQ(cost_before_junction(side, false, true), 0);
}

TEST(CurvatureWindow, FollowsTheSameNameNeverTheSideRoad) {
  // The main road changes way at the junction (ways 100 and 101, both "Hlavní"); the side road
  // is way 300 "Boční". The window follows the name, not the side road.
  const auto t_junction = [](const std::string& continued_name) {
    GraphBuilder b;
    b.add_piece(1, 2, straight({0, 0}, {200, 0}), "residential", 10.0, 100, "Hlavní");
    b.add_piece(2, 3, straight({200, 0}, {400, 0}), "residential", 10.0, 101, continued_name);
    b.add_piece(2, 4, straight({200, 0}, {200, 100}), "residential", 10.0, 300, "Boční");
    return b;
  };
  GraphBuilder named = t_junction("Hlavní");
  EXPECT_EQ(cost_before_junction(named, true, true), 1);
  // A bend on the side road, 30..40 m from the junction: not in the main road's window (0).
  GraphBuilder side = t_junction("Hlavní");
  EXPECT_EQ(cost_before_junction(side, false, true), 0);
  // Another name beyond the junction: the road ends there, as at a dead end (0).
  GraphBuilder other = t_junction("Jiná");
  EXPECT_EQ(cost_before_junction(other, true, true), 0);
}

TEST(CurvatureWindow, SideRoadEndingAtTheJunctionDoesNotEnterTheMainRoad) {
  // The side road's segment at the junction (midpoint 5 m from it, window -95..105 clipped to
  // its 100 m): with a bend on the main road 30..40 m beyond the junction it would see it if the
  // window turned into the main road; it ends at the junction, so all 0.75 -> 0. Its level-5
  // segments are set to 0 by hand as in cost_before_junction.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {200, 0}), "residential", 10.0, 100, "Hlavní");
  b.add_piece(2, 3, straight({200, 0}, {400, 0}), "residential", 10.0, 100, "Hlavní");
  b.add_piece(2, 4, straight({200, 0}, {200, 100}), "residential", 10.0, 300, "Boční");
  cost_before_junction(b, true, true);
  EXPECT_EQ(*b.graph.segments[40].curvature_cost, 0);  // first of 2-4, touching the junction
}

TEST(Strokes, ChainThroughDegreeTwoAndStopAtJunctions) {
  // 1 -> 2 <- 3 (the second piece drawn backwards) joined at degree-2 node 2, then a junction at
  // 3 with two more roads. The first stroke runs 1..3 with the second piece reversed.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {30, 0}));
  b.add_piece(3, 2, straight({60, 0}, {30, 0}));
  b.add_piece(3, 4, straight({60, 0}, {90, 0}));
  b.add_piece(3, 5, straight({60, 0}, {60, 30}));
  const auto strokes = rp::build_strokes(b.graph);
  ASSERT_EQ(strokes.size(), 3u);
  const rp::Stroke& first = strokes[0];
  EXPECT_NEAR(first.length_m, 60.0, 1e-9);
  ASSERT_EQ(first.segments.size(), 6u);
  EXPECT_FALSE(first.segments[0].reversed);
  EXPECT_TRUE(first.segments[3].reversed);
  EXPECT_NEAR(first.segments[3].start_m, 30.0, 1e-9);
  EXPECT_NEAR(first.segments[5].end_m, 60.0, 1e-9);
  EXPECT_EQ(first.points.size(), 3u);  // the joint is not repeated
}

TEST(Strokes, IsolatedRoundaboutIsAClosedStroke) {
  GraphBuilder b;
  std::vector<PlanePoint> ring = arc(20, 2, 2 * kPi);
  ring.back() = ring.front();
  b.add_piece(1, 1, ring);
  const auto strokes = rp::build_strokes(b.graph);
  ASSERT_EQ(strokes.size(), 1u);
  EXPECT_TRUE(strokes[0].closed);
  rp::compute_geometry_costs(b.graph, {});
  // Every segment of a 20 m ring has the ring's radius (no open ends on a ring).
  for (const rp::Segment& s : b.graph.segments) EXPECT_NEAR(*s.radius_m, 20.0, 2.0);
}

TEST(Strokes, ParallelVisitsTheSameStrokesAsTheSerialWalk) {
  // A grid of streets, each row and column one way drawn with a wiggle, cut at every crossing:
  // chains through degree-2 nodes (the wiggles' joints), junctions, dead ends and a ring; ~100k
  // segments, several of for_each_stroke_parallel's batches.
  GraphBuilder b;
  constexpr int kN = 40;
  const auto node = [](int i, int j, int part) {
    return static_cast<std::int64_t>((i * kN + j) * 4 + part + 10);
  };
  for (int i = 0; i < kN; ++i) {
    for (int j = 0; j + 1 < kN; ++j) {
      const double x = 100.0 * j, y = 100.0 * i;
      // Along the row: two pieces joined at a degree-2 node, the second drawn backwards.
      b.add_piece(node(i, j, 0), node(i, j, 1), {{x, y}, {x + 25, y + 3}, {x + 50, y}}, "tertiary",
                  2.0, 5000 + i);
      b.add_piece(node(i, j + 1, 0), node(i, j, 1), {{x + 100, y}, {x + 75, y - 2}, {x + 50, y}},
                  "tertiary", 2.0, 5000 + i);
      // Along the column (left out in every fifth column: dead ends and degree-2 row nodes).
      if (j % 5 == 4) continue;
      const double cx = 100.0 * i, cy = 100.0 * j;
      b.add_piece(node(j, i, 0), node(j + 1, i, 0), {{cx, cy}, {cx + 4, cy + 50}, {cx, cy + 100}},
                  "residential", 3.0, 9000 + i);
    }
  }
  std::vector<PlanePoint> ring = arc(20, 2, 2 * kPi);
  ring.back() = ring.front();
  b.add_piece(1, 1, ring);
  ASSERT_GT(b.graph.segments.size(), 100000u);

  // Each stroke recorded under its first segment (strokes share no segment).
  using Record = std::vector<double>;
  const auto record = [](const rp::Stroke& stroke) {
    Record r = {stroke.length_m, stroke.closed ? 1.0 : 0.0,
                static_cast<double>(stroke.points.size())};
    for (const PlanePoint& p : stroke.points) r.insert(r.end(), {p.x, p.y});
    for (const rp::StrokeSegment& s : stroke.segments) {
      r.insert(r.end(),
               {static_cast<double>(s.segment), s.reversed ? 1.0 : 0.0, s.start_m, s.end_m});
    }
    return r;
  };
  std::vector<Record> serial(b.graph.segments.size()), parallel(b.graph.segments.size());
  std::size_t serial_count = 0;
  rp::for_each_stroke(b.graph, [&](const rp::Stroke& stroke) {
    serial[stroke.segments.front().segment] = record(stroke);
    ++serial_count;
  });
  std::atomic<std::size_t> parallel_count{0};
  const rp::Incidences incidences(b.graph);
  rp::for_each_stroke_parallel(b.graph, incidences, [&](const rp::Stroke& stroke) {
    parallel[stroke.segments.front().segment] = record(stroke);
    ++parallel_count;
  });
  EXPECT_GT(serial_count, 1000u);
  EXPECT_EQ(parallel_count, serial_count);
  EXPECT_TRUE(serial == parallel);

  // The costs from the parallel strokes: the same on a second run, and set on every segment.
  rp::compute_geometry_costs(b.graph, {});
  std::vector<std::pair<int, float>> first;
  for (const rp::Segment& s : b.graph.segments) {
    ASSERT_TRUE(s.curvature_cost && s.radius_m);
    first.emplace_back(*s.curvature_cost, *s.radius_m);
  }
  rp::compute_geometry_costs(b.graph, {});
  for (std::size_t k = 0; k < first.size(); ++k) {
    ASSERT_EQ(*b.graph.segments[k].curvature_cost, first[k].first) << k;
    ASSERT_EQ(*b.graph.segments[k].radius_m, first[k].second) << k;
  }
}

// ---- The elevation cost: the method's scale and window. -------------------------------------

TEST(ElevationCost, MethodScaleIsTheFlooredMeanCappedAtNine) {
  // min(9, floor(M)) of the window's mean landform cost M. The former floor(M * 9 / 15) gave
  // 2, 4, 5, 6 and 9 here: a ridge (8) scored 4 and a midslope ridge (10) 6.
  EXPECT_EQ(rp::elevation_cost_of(4.0), 4);
  EXPECT_EQ(rp::elevation_cost_of(8.0), 8);
  EXPECT_EQ(rp::elevation_cost_of(9.0), 9);
  EXPECT_EQ(rp::elevation_cost_of(10.0), 9);
  EXPECT_EQ(rp::elevation_cost_of(15.0), 9);
  // Floored, not rounded; an exact mean summed in floating point is not floored one lower.
  EXPECT_EQ(rp::elevation_cost_of(8.99), 8);
  EXPECT_EQ(rp::elevation_cost_of(0.1 + 0.2 + 7.7), 8);
  EXPECT_EQ(rp::elevation_cost_of(0.0), 0);
}

/// Every segment on flat ground with zero TPI (plains, landform cost 1), except those in
/// `tops`: standardised TPI +3 at both scales (mountain top, cost 15).
void set_landforms(rp::RoadGraph& graph, const std::vector<std::size_t>& tops) {
  for (std::size_t i = 0; i < graph.segments.size(); ++i) {
    rp::Segment& s = graph.segments[i];
    const bool top = std::find(tops.begin(), tops.end(), i) != tops.end();
    s.elevation_m = 100.0f;
    s.slope_deg = 0.0f;
    s.tpi_small_m = top ? 3.0f : 0.0f;
    s.tpi_large_m = top ? 3.0f : 0.0f;
  }
}

TEST(ElevationCost, EvaluatedSegmentIsNotCountedInItsWindow) {
  // A 400 m road of 10 m segments; segments 20..24 (200..250 m) on a mountain top. Segment 22
  // (midpoint 225 m), window 125..325 m without itself: 40 m of mountain top (15) and 150 m of
  // plains (1): (600 + 150) / 190 = 3.95 -> 3. Counted 3 times, as before, it would be
  // (450 + 600 + 150) / 220 = 5.45 -> 5.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {400, 0}));
  set_landforms(b.graph, {20, 21, 22, 23, 24});
  rp::TpiStandardisation unit;  // mean 0, SD 1: the TPI values are the standardised ones
  rp::assign_terrain(b.graph, std::vector<rp::StructureEnds>{}, unit, rp::TerrainParameters{});
  EXPECT_STREQ(b.graph.segments[22].landform.text(), "mountain_top");
  EXPECT_EQ(*b.graph.segments[22].elevation_cost, 3);
  // Segment 0 (window 0..105 m without itself): 95 m of plains -> 1.
  EXPECT_EQ(*b.graph.segments[0].elevation_cost, 1);

  // A road of one segment has nothing else in its window: its own landform is used.
  GraphBuilder lone;
  lone.add_piece(1, 2, straight({0, 0}, {8, 0}));
  set_landforms(lone.graph, {0});
  rp::assign_terrain(lone.graph, std::vector<rp::StructureEnds>{}, unit, rp::TerrainParameters{});
  EXPECT_EQ(*lone.graph.segments[0].elevation_cost, 9);  // min(9, 15)
  EXPECT_FALSE(lone.graph.segments[0].reasons.contains("NO_ELEVATION"));
}

// ---- Class, tunnel, rank. --------------------------------------------------------------------

TEST(ClassCost, DesignTable) {
  const rp::GeometryParameters p;
  EXPECT_EQ(rp::class_cost("primary", p), 5);
  EXPECT_EQ(rp::class_cost("primary_link", p), 5);
  EXPECT_EQ(rp::class_cost("secondary", p), 4);
  EXPECT_EQ(rp::class_cost("tertiary_link", p), 3);
  EXPECT_EQ(rp::class_cost("busway", p), 3);
  EXPECT_EQ(rp::class_cost("residential", p), 2);
  EXPECT_EQ(rp::class_cost("living_street", p), 2);
  EXPECT_EQ(rp::class_cost("service", p), 2);
  EXPECT_EQ(rp::class_cost("road", p), 2);
  EXPECT_EQ(rp::class_cost("unclassified", p), 1);
  EXPECT_EQ(rp::class_cost("motorway", p), 5);
}

TEST(ClassCost, MotorwayAndTunnelReasons) {
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {30, 0}), "motorway");
  b.add_piece(3, 4, straight({0, 100}, {30, 100}), "trunk_link");
  b.add_piece(5, 6, straight({0, 200}, {30, 200}), "residential");
  for (rp::Segment& s : b.graph.segments) s.tunnel = s.piece_index == 2;
  rp::compute_geometry_costs(b.graph, {});
  EXPECT_EQ(b.graph.segments[0].reasons.list(), std::vector<std::string>{"NOT_CROSSABLE_CLASS"});
  EXPECT_EQ(b.graph.segments[3].reasons.list(), std::vector<std::string>{"NOT_CROSSABLE_CLASS"});
  EXPECT_EQ(b.graph.segments[6].reasons.list(), std::vector<std::string>{"TUNNEL"});
}

TEST(Rank, FormulaEdgesAndReachability) {
  const rp::RankParameters p;
  // Without elevation: 15 * (70 c/14 + 5 k/5) / 75.
  EXPECT_EQ(rp::rank_of(0, 1, std::nullopt, p), 0);    // 15 * 1 / 75 = 0.2
  EXPECT_EQ(rp::rank_of(0, 5, std::nullopt, p), 1);    // 15 * 5 / 75 = 1
  EXPECT_EQ(rp::rank_of(0, 2, std::nullopt, p), 0);    // 0.4: a quiet straight residential road
  EXPECT_EQ(rp::rank_of(14, 0, std::nullopt, p), 14);  // 15 * 70 / 75 = 14 exactly
  EXPECT_EQ(rp::rank_of(14, 5, std::nullopt, p), 14);  // 15, clamped
  EXPECT_EQ(rp::rank_of(7, 2, std::nullopt, p), 7);    // 15 * (35 + 2) / 75 = 7.4
  // With elevation: 15 * (70 c/14 + 5 k/5 + 25 e/9) / 100.
  EXPECT_EQ(rp::rank_of(0, 2, 0, p), 0);    // 0.3
  EXPECT_EQ(rp::rank_of(0, 2, 9, p), 4);    // 15 * 27 / 100 = 4.05
  EXPECT_EQ(rp::rank_of(14, 5, 9, p), 14);  // 15, clamped
  EXPECT_EQ(rp::rank_of(13, 2, 9, p), 13);  // 15 * (65 + 2 + 25) / 100 = 13.8
  EXPECT_EQ(rp::rank_of(14, 0, 9, p), 14);  // 15 * 95 / 100 = 14.25
}

TEST(Rank, BothEndsOccurForRealInputs) {
  // A quiet straight residential road far from junctions ranks 0; a segment at a junction of a
  // primary road (curvature cost 14 around it) ranks 14.
  GraphBuilder b;
  b.add_piece(1, 2, straight({0, 0}, {400, 0}), "residential");
  // A star of five short primary roads: everything is within a few metres of the junction.
  for (int k = 0; k < 5; ++k) {
    const double t = 2 * kPi * k / 5;
    b.add_piece(10, 20 + k, straight({1000, 0}, {1000 + 20 * std::cos(t), 20 * std::sin(t)}),
                "primary");
  }
  rp::compute_geometry_costs(b.graph, {});
  rp::compute_ranks(b.graph, {});
  EXPECT_EQ(*b.graph.segments[20].rank, 0);
  EXPECT_EQ(*b.graph.segments[20].score(), 15);
  const rp::Segment& at_junction = b.graph.segments[40];
  EXPECT_EQ(*at_junction.curvature_level, 5);
  EXPECT_EQ(*at_junction.curvature_cost, 14);  // floor(30) clamped
  EXPECT_EQ(*at_junction.rank, 14);
  EXPECT_EQ(*at_junction.score(), 1);
}

TEST(Parameters, ValidationNamesTheParameter) {
  rp::Parameters p;
  p.geometry.window_half_length_m = -5;
  try {
    p.validate();
    FAIL() << "expected ParameterError";
  } catch (const rp::ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry.window_half_length_m"), std::string::npos);
  }
  rp::Parameters q;
  q.geometry.class_cost_primary = 4.5;
  EXPECT_THROW(q.validate(), rp::ParameterError);  // must be whole
  // Level radii must not increase from level 4 to level 1 (each in range on its own).
  rp::Parameters levels;
  levels.geometry.level3_radius_m = 30;  // below level 4's 40 m: level 3 could never occur
  try {
    levels.validate();
    FAIL() << "expected ParameterError";
  } catch (const rp::ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("geometry.level3_radius_m"), std::string::npos);
  }
  levels.geometry.level3_radius_m = 40;  // equal: level 3 empty on purpose, allowed
  EXPECT_NO_THROW(levels.validate());
  rp::Parameters ok;
  EXPECT_NO_THROW(ok.validate());
  bool recorded = false;
  for (const auto& [key, value] : ok.as_metadata()) {
    if (key == "param.geometry.level5_weight") recorded = value == "30";
  }
  EXPECT_TRUE(recorded);
}

}  // namespace
