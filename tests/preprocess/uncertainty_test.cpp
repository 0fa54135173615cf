// Map::assess, road_heading and better_place under position uncertainty, on hand-made maps.
//
// The share on suitable places is the Gaussian mass on suitable places divided by the region's
// mass p. For a circular (or whitened) Gaussian and a straight road whose suitable part ends at
// a line across the road `a` standard deviations ahead of the fix, the places nearer to the
// next segment are exactly those beyond that line, so with k^2 = -2 ln(1 - p) the region's
// radius in standard units and phi, Phi the standard normal density and distribution:
//   share(a) = 1/p * integral_{-k}^{min(a, k)} phi(u) (2 Phi(sqrt(k^2 - u^2)) - 1) du
// (the inner factor is the mass of the chord at u). truncated_share() integrates this in one
// dimension with Simpson's rule; the runtime samples rings in two, so the two are independent.
// As p -> 1 the share tends to Phi(a), the plain Gaussian share on one side of a line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
using roadcross::Map;
using roadcross::Position;
using roadcross::PositionUncertainty;
using roadcross::StatusCode;

namespace {

double normal_cdf(double x) {
  return 0.5 * std::erfc(-x / std::sqrt(2.0));
}

double truncated_share(double a, double p) {
  const double k = std::sqrt(-2.0 * std::log(1.0 - p));
  const double upper = std::min(a, k);
  if (upper <= -k) return 0.0;
  const int n = 4000;  // even
  const double h = (upper + k) / n;
  const auto f = [&](double u) {
    const double chord = std::sqrt(std::max(k * k - u * u, 0.0));
    return std::exp(-0.5 * u * u) / std::sqrt(2.0 * M_PI) * (2.0 * normal_cdf(chord) - 1.0);
  };
  double sum = f(-k) + f(upper);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(-k + i * h);
  return sum * h / 3.0 / p;
}

bool has(const roadcross::Assessment& a, const std::string& code) {
  return std::find(a.reasons.begin(), a.reasons.end(), code) != a.reasons.end();
}

Map build(const rt::TempDir& dir, const std::string& body) {
  const std::string osm = dir.write("map.osm", rt::osm_document(body));
  rp::BuildOptions options;
  options.osm_path = osm;
  options.output_path = dir.file("map.gpkg");
  rp::run_build(options);
  auto map = Map::open(options.output_path);
  if (!map.ok()) throw std::runtime_error(map.status.message);
  return std::move(*map.value);
}

Position utm_of(Map& map, double lat, double lon, double east_m = 0.0, double north_m = 0.0) {
  const auto p = map.to_utm(Position::wgs84(lat, lon));
  return Position::utm(p->easting_m + east_m, p->northing_m + north_m);
}

/// A covariance with standard deviations `along_m` in direction `yaw_rad` and `across_m`
/// perpendicular to it: R diag(along^2, across^2) R^T.
PositionUncertainty oriented(double yaw_rad, double along_m, double across_m,
                             PositionUncertainty::Frame frame = PositionUncertainty::Frame::grid) {
  const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
  const double a2 = along_m * along_m, b2 = across_m * across_m;
  PositionUncertainty u;
  u.frame = frame;
  u.east_east_m2 = c * c * a2 + s * s * b2;
  u.east_north_m2 = c * s * (a2 - b2);
  u.north_north_m2 = s * s * a2 + c * c * b2;
  return u;
}

// A straight east-west street of two ways with the same name: 50.0 N from 14.40 to 14.4083 E
// (about 600 m), then in a tunnel to 14.4166 E. Node 2 ends the open part; no junction.
class StraightStreet : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new rt::TempDir;
    map_ = new Map(build(
        *dir_, rt::osm_node(1, 50.0, 14.40) + rt::osm_node(2, 50.0, 14.4083) +
                   rt::osm_node(3, 50.0, 14.4166) +
                   rt::osm_way(10, "1 2", "highway=residential;name=Test Street") +
                   rt::osm_way(11, "2 3", "highway=residential;name=Test Street;tunnel=yes")));
  }
  static void TearDownTestSuite() {
    delete map_;
    delete dir_;
  }
  /// `back_m` west of the tunnel's portal (node 2) along the road, `north_m` off it.
  static Position before_portal(double back_m, double north_m) {
    const auto heading = map_->road_heading(utm_of(*map_, 50.0, 14.4083, -5.0, 0.0));
    const double yaw = heading->road_heading_rad;  // the way's direction, east
    const auto portal = map_->to_utm(Position::wgs84(50.0, 14.4083));
    return Position::utm(portal->easting_m - back_m * std::cos(yaw) - north_m * std::sin(yaw),
                         portal->northing_m - back_m * std::sin(yaw) + north_m * std::cos(yaw));
  }
  static double road_yaw() {
    return map_->road_heading(before_portal(50.0, 0.0))->road_heading_rad;
  }
  static rt::TempDir* dir_;
  static Map* map_;
};
rt::TempDir* StraightStreet::dir_ = nullptr;
Map* StraightStreet::map_ = nullptr;

TEST_F(StraightStreet, FarFromTheTunnelTheAnswerIsTheExactOne) {
  const Position fix = before_portal(300.0, 3.0);
  const auto exact = map_->assess(fix);
  ASSERT_TRUE(exact.ok()) << exact.status.message;
  ASSERT_TRUE(exact->suitable);
  for (const double sigma_m : {1.0, 3.0}) {
    const auto uncertain = map_->assess(fix.with_sigma(sigma_m));
    ASSERT_TRUE(uncertain.ok()) << uncertain.status.message;
    EXPECT_TRUE(uncertain->suitable);
    EXPECT_EQ(uncertain->reasons, exact->reasons);
    EXPECT_EQ(uncertain->road.segment_id, exact->road.segment_id);
    EXPECT_EQ(uncertain->score, exact->score);
    EXPECT_EQ(uncertain->context_score, exact->context_score);
    ASSERT_TRUE(uncertain->region.has_value());
    EXPECT_DOUBLE_EQ(uncertain->region->suitable_share, 1.0);
    EXPECT_TRUE(uncertain->region->same_road);
    EXPECT_LT(uncertain->region->heading_spread_rad, 1e-6);  // one straight edge
    EXPECT_EQ(uncertain->region->segment_ids.front(), exact->road.segment_id);
    // k = sqrt(-2 ln 0.05) = 2.44775 standard deviations.
    EXPECT_NEAR(uncertain->region->semi_major_m, 2.44775 * sigma_m, 1e-4);
    EXPECT_NEAR(uncertain->region->semi_minor_m, 2.44775 * sigma_m, 1e-4);
  }
  EXPECT_FALSE(exact->region.has_value());
}

TEST_F(StraightStreet, TheShareBeforeThePortalIsTheGaussianShareOnOneSideOfALine) {
  // 2 m before the portal with sigma 2 m: the tunnel begins a = 1 standard deviation ahead.
  const Position fix = before_portal(2.0, 3.0);
  const auto exact = map_->assess(fix);
  ASSERT_TRUE(exact.ok()) << exact.status.message;
  ASSERT_TRUE(exact->suitable);  // the open way's last segment is suitable
  const auto a = map_->assess(fix.with_sigma(2.0));
  ASSERT_TRUE(a.ok()) << a.status.message;
  EXPECT_FALSE(a->suitable);
  EXPECT_TRUE(has(*a, "POSITION_UNCERTAIN"));
  EXPECT_FALSE(has(*a, "AMBIGUOUS_ROAD"));  // both ways are Test Street
  EXPECT_TRUE(a->region->same_road);
  EXPECT_GE(a->region->segment_ids.size(), 2u);
  // share(1, 0.95) = 0.8650 (Phi(1) = 0.8413 on the whole plane).
  EXPECT_NEAR(a->region->suitable_share, truncated_share(1.0, 0.95), 0.01);
  // Nearly the whole plane: the share tends to Phi(1).
  const auto wide = map_->assess(fix.with_sigma(2.0, 0.9999));
  ASSERT_TRUE(wide.ok());
  EXPECT_NEAR(wide->region->suitable_share, normal_cdf(1.0), 0.01);
  // Half a standard deviation past the portal: share(-0.5) = 0.3...
  const auto past = map_->assess(before_portal(-1.0, 3.0).with_sigma(2.0));
  ASSERT_TRUE(past.ok());
  EXPECT_FALSE(past->suitable);
  EXPECT_NEAR(past->region->suitable_share, truncated_share(-0.5, 0.95), 0.01);
}

TEST_F(StraightStreet, AnEllipseAlongTheRoadReachesTheTunnelOneAcrossItDoesNot) {
  const Position fix = before_portal(2.0, 3.0);
  const double yaw = road_yaw();
  // Along: sigma 3 m along the road, 0.3 m across. The portal is a = 2/3 ahead.
  const auto along = map_->assess(fix.with_uncertainty(oriented(yaw, 3.0, 0.3)));
  ASSERT_TRUE(along.ok()) << along.status.message;
  EXPECT_FALSE(along->suitable);
  EXPECT_TRUE(has(*along, "POSITION_UNCERTAIN"));
  EXPECT_NEAR(along->region->suitable_share, truncated_share(2.0 / 3.0, 0.95), 0.01);
  EXPECT_NEAR(along->region->semi_major_m, 2.44775 * 3.0, 1e-3);
  EXPECT_NEAR(along->region->semi_minor_m, 2.44775 * 0.3, 1e-3);
  EXPECT_NEAR(std::remainder(along->region->major_axis_yaw_rad - yaw, M_PI), 0.0, 1e-9);
  // Across: the region reaches 2.45 x 0.3 = 0.73 m along the road, short of the portal.
  const auto across = map_->assess(fix.with_uncertainty(oriented(yaw, 0.3, 3.0)));
  ASSERT_TRUE(across.ok()) << across.status.message;
  EXPECT_TRUE(across->suitable);
  EXPECT_DOUBLE_EQ(across->region->suitable_share, 1.0);
  EXPECT_FALSE(has(*across, "POSITION_UNCERTAIN"));
}

TEST_F(StraightStreet, AnEnuCovarianceIsTurnedIntoTheGridByTheConvergence) {
  const Position fix = before_portal(2.0, 3.0);
  const auto heading = map_->road_heading(fix);
  ASSERT_TRUE(heading.ok());
  // The road's true ENU direction is its grid direction plus the convergence; an ellipse along
  // it in ENU must land along the road in the grid and give the grid ellipse's answer.
  const double true_yaw = heading->road_heading_rad + heading->convergence_rad;
  ASSERT_GT(std::abs(heading->convergence_rad), 0.005);  // 14.4 E in zone 33: about -0.46 deg
  const auto enu = map_->assess(
      fix.with_uncertainty(oriented(true_yaw, 3.0, 0.3, PositionUncertainty::Frame::enu)));
  const auto grid =
      map_->assess(fix.with_uncertainty(oriented(heading->road_heading_rad, 3.0, 0.3)));
  ASSERT_TRUE(enu.ok() && grid.ok());
  EXPECT_NEAR(std::remainder(enu->region->major_axis_yaw_rad - heading->road_heading_rad, M_PI),
              0.0, 1e-6);
  EXPECT_DOUBLE_EQ(enu->region->suitable_share, grid->region->suitable_share);
  // Taken as grid, the same matrix is turned by the convergence against the road.
  const auto wrong = map_->assess(fix.with_uncertainty(oriented(true_yaw, 3.0, 0.3)));
  EXPECT_NEAR(std::remainder(wrong->region->major_axis_yaw_rad - heading->road_heading_rad, M_PI),
              heading->convergence_rad, 1e-6);
}

TEST_F(StraightStreet, ZeroNegativeAndNonFiniteUncertaintyIsAnError) {
  const Position fix = before_portal(300.0, 3.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const double sigma_m : {0.0, -1.0, nan, inf}) {
    const auto a = map_->assess(fix.with_sigma(sigma_m));
    EXPECT_EQ(a.status.code, StatusCode::invalid_argument) << sigma_m;
    EXPECT_NE(a.status.message.find("position uncertainty"), std::string::npos);
    EXPECT_EQ(map_->road_heading(fix.with_sigma(sigma_m)).status.code,
              StatusCode::invalid_argument);
    EXPECT_EQ(map_->better_place(fix.with_sigma(sigma_m)).status.code,
              StatusCode::invalid_argument);
  }
  PositionUncertainty singular;  // [[1, 1], [1, 1]]: not positive definite
  singular.east_east_m2 = singular.east_north_m2 = singular.north_north_m2 = 1.0;
  EXPECT_EQ(map_->assess(fix.with_uncertainty(singular)).status.code, StatusCode::invalid_argument);
  for (const double p : {0.0, 1.0, nan}) {
    EXPECT_EQ(map_->assess(fix.with_sigma(1.0, p)).status.code, StatusCode::invalid_argument);
  }
}

TEST_F(StraightStreet, BetterPlacesStaySuitableUnderTheSameUncertainty) {
  // 2 m before the portal: exact, the place itself and candidates back along the open way are
  // suitable; under sigma 2 m a candidate is only one whose own region stays clear of the
  // tunnel (the candidates are segment midpoints, so the nearest one to the portal may not).
  const Position fix = before_portal(2.0, 3.0);
  const auto exact = map_->better_place(fix);
  const auto uncertain = map_->better_place(fix.with_sigma(2.0));
  ASSERT_TRUE(exact.ok() && uncertain.ok()) << uncertain.status.message;
  ASSERT_FALSE(uncertain->candidates.empty());
  for (const auto& c : uncertain->candidates) {
    ASSERT_TRUE(c.suitable_share.has_value());
    if (!c.suitable) continue;
    EXPECT_DOUBLE_EQ(*c.suitable_share, 1.0);
    const auto there =
        map_->assess(Position::utm(c.point.easting_m, c.point.northing_m).with_sigma(2.0));
    EXPECT_TRUE(there->suitable);
  }
  for (const auto& c : exact->candidates) EXPECT_FALSE(c.suitable_share.has_value());
}

TEST_F(StraightStreet, BetterPlacesFromFarOffTheRoadWalkFromTheNearestPoint) {
  // 150 m north of the street, beyond the 100 m search radius and its 20 m margin: the walk
  // starts where the robot would reach the road, so the same segments are offered as from
  // 5 m north of that point (their walking distances are the same; the places stand at the
  // robot's offset, which differs). It once answered "own segment not indexed", a damaged
  // map, because the neighbourhood was read around the robot.
  const auto far = map_->better_place(before_portal(200.0, 150.0));
  const auto near = map_->better_place(before_portal(200.0, 5.0));
  ASSERT_TRUE(far.ok()) << far.status.message;
  ASSERT_TRUE(near.ok()) << near.status.message;
  ASSERT_FALSE(near->candidates.empty());
  ASSERT_EQ(far->candidates.size(), near->candidates.size());
  for (std::size_t i = 0; i < near->candidates.size(); ++i) {
    EXPECT_EQ(far->candidates[i].segment_id, near->candidates[i].segment_id);
    EXPECT_NEAR(far->candidates[i].walking_distance_m, near->candidates[i].walking_distance_m,
                1e-6);
  }
}

// A trunk road: every segment carries NOT_CROSSABLE_CLASS, which the map reader checks against
// the segment's highway class. The region's segments are judged by the same checks, so their
// class must be read too (it once was selected as NULL there, and every region near a trunk or
// motorway was reported as a damaged map).
TEST(TrunkRoad, TheRegionIsNotCrossableNotADamagedMap) {
  rt::TempDir dir;
  Map map = build(dir, rt::osm_node(1, 50.0, 14.40) + rt::osm_node(2, 50.0, 14.404) +
                           rt::osm_way(10, "1 2", "highway=trunk;name=Bypass"));
  const Position fix = utm_of(map, 50.0, 14.402, 0.0, 2.0);  // mid-way, 2 m north
  const auto exact = map.assess(fix);
  ASSERT_TRUE(exact.ok()) << exact.status.message;
  EXPECT_TRUE(has(*exact, "NOT_CROSSABLE_CLASS"));
  const auto uncertain = map.assess(fix.with_sigma(3.0));
  ASSERT_TRUE(uncertain.ok()) << uncertain.status.message;
  EXPECT_FALSE(uncertain->suitable);
  // Segments of about 10 m and a region of radius 7.3 m: more than one segment, all of them
  // on the one way and none suitable.
  EXPECT_GT(uncertain->region->segment_ids.size(), 1u);
  EXPECT_TRUE(uncertain->region->same_road);
  EXPECT_EQ(uncertain->region->suitable_share, 0.0);
  EXPECT_FALSE(has(*uncertain, "POSITION_UNCERTAIN"));
}

// A T junction: Main Street east-west along 50.0 N, an unnamed side road north from its
// middle node 2 (50.0 N, 14.404 E).
class TJunction : public ::testing::Test {
 protected:
  void SetUp() override {
    map_.emplace(build(dir_, rt::osm_node(1, 50.0, 14.40) + rt::osm_node(2, 50.0, 14.404) +
                                 rt::osm_node(3, 50.0, 14.408) + rt::osm_node(4, 50.002, 14.404) +
                                 rt::osm_way(10, "1 2 3", "highway=residential;name=Main Street") +
                                 rt::osm_way(20, "2 4", "highway=residential")));
  }
  rt::TempDir dir_;
  std::optional<Map> map_;
};

TEST_F(TJunction, NorthOfMainStreetFourMetresFromTheSideRoadIsAmbiguous) {
  // 4 m west of the side road and 2.5 m north of Main Street: Main is nearer (2.5 < 4). The
  // places equally far from both lie on the corner's bisector, |-4 + 2.5| / sqrt(2) = 1.06 m
  // away: sigma 1 m (region radius 2.45 m) reaches it, sigma 0.2 m (0.49 m) does not.
  const Position fix = utm_of(*map_, 50.0, 14.404, -4.0, 2.5);
  const auto exact = map_->assess(fix);
  ASSERT_TRUE(exact.ok()) << exact.status.message;
  EXPECT_EQ(exact->road.osm_way_id, 10);
  const auto tight = map_->assess(fix.with_sigma(0.2));
  ASSERT_TRUE(tight.ok()) << tight.status.message;
  EXPECT_FALSE(has(*tight, "AMBIGUOUS_ROAD"));
  EXPECT_TRUE(tight->region->same_road);
  EXPECT_LT(tight->region->heading_spread_rad, 0.01);
  EXPECT_EQ(tight->suitable, exact->suitable);
  const auto loose = map_->assess(fix.with_sigma(1.0));
  ASSERT_TRUE(loose.ok()) << loose.status.message;
  EXPECT_TRUE(has(*loose, "AMBIGUOUS_ROAD"));
  EXPECT_FALSE(loose->suitable);
  EXPECT_FALSE(loose->region->same_road);
  // Some places are nearest the side road, which runs north: a quarter turn from Main.
  EXPECT_NEAR(loose->region->heading_spread_rad, M_PI / 2.0, 0.02);
  const auto heading = map_->road_heading(fix.with_sigma(1.0));
  ASSERT_TRUE(heading.ok());
  EXPECT_NEAR(*heading->heading_spread_rad, M_PI / 2.0, 0.02);
  EXPECT_FALSE(map_->road_heading(fix)->heading_spread_rad.has_value());
}

TEST_F(TJunction, SouthOfMainStreetNoSideRoadIsNear) {
  // The mirror place south of Main: the region (radius 2.45 m) stays south of Main's centreline
  // (2.5 m away) and 4.7 m from the side road's end node.
  const Position fix = utm_of(*map_, 50.0, 14.404, -4.0, -2.5);
  const auto loose = map_->assess(fix.with_sigma(1.0));
  ASSERT_TRUE(loose.ok()) << loose.status.message;
  EXPECT_FALSE(has(*loose, "AMBIGUOUS_ROAD"));
  EXPECT_TRUE(loose->region->same_road);
  for (const auto id : loose->region->segment_ids) {
    EXPECT_EQ(map_->assess_segment(id)->road.osm_way_id, 10);
  }
}

// A bend: a residential road east along 50.0 N for 300 m, then a quarter circle of radius
// 15 m (a vertex every 15 degrees) turning north, then 300 m north. Local metres x east, y north
// around node 1, converted with 111 229 m a degree of latitude and 71 555 m a degree of longitude
// at 50 N (the test measures in UTM anyway). The build cuts it into 9.9 m segments and marks the
// five around the arc SHARP_BEND with the highest curvature cost: score 10 + context 10 = 20,
// one point below the others' 21 or more, so with the threshold at 21 (a per-call override)
// exactly those five are unsuitable, the first of them beginning on the straight leg.
std::string bend_osm() {
  std::string nodes;
  std::string refs;
  const auto add = [&](long id, double x_m, double y_m) {
    nodes += rt::osm_node(id, 50.0 + y_m / 111229.0, 14.40 + x_m / 71555.0);
    refs += (refs.empty() ? "" : " ") + std::to_string(id);
  };
  add(1, 0.0, 0.0);
  for (int step = 0; step <= 6; ++step) {
    const double angle = step * M_PI / 12.0;
    add(2 + step, 300.0 + 15.0 * std::sin(angle), 15.0 - 15.0 * std::cos(angle));
  }
  add(9, 315.0, 315.0);
  return nodes + rt::osm_way(10, refs, "highway=residential;name=Bend Street");
}

TEST(Bend, ARegionReachingTheOneUnsuitableSegmentMakesThePositionUncertain) {
  rt::TempDir dir;
  Map map = build(dir, bend_osm());
  const auto at = [&](double x_m, double y_m) {
    return utm_of(map, 50.0, 14.40 + 300.0 / 71555.0, x_m - 300.0, y_m);
  };
  // Walk west along the first leg, 3 m south of it (the bend's outside), from the arc to the
  // first suitable place: just beyond it the unsuitable segment begins.
  roadcross::AssessOptions options;
  options.threshold = 21.0;
  ASSERT_FALSE(map.assess(at(300.0, -3.0), options)->suitable) << "the arc is not unsuitable";
  double back_m = 0.0;
  for (; back_m < 200.0; back_m += 0.5) {
    const auto a = map.assess(at(300.0 - back_m, -3.0), options);
    ASSERT_TRUE(a.ok()) << a.status.message;
    if (a->suitable) break;
  }
  ASSERT_LT(back_m, 200.0) << "no suitable place on the first leg";
  const Position fix = at(300.0 - back_m - 0.5, -3.0);
  const auto exact = map.assess(fix, options);
  ASSERT_TRUE(exact->suitable);
  // Sigma 0.1 m: the region (0.24 m) stays on the suitable segment.
  const auto tight = map.assess(fix.with_sigma(0.1), options);
  ASSERT_TRUE(tight.ok());
  EXPECT_TRUE(tight->suitable);
  EXPECT_DOUBLE_EQ(tight->region->suitable_share, 1.0);
  // Sigma 1 m: the fix is 0.5 to 1 m (sigma) before the unsuitable segment's start (the places
  // nearer to it lie beyond the line across the road at its first vertex).
  const auto loose = map.assess(fix.with_sigma(1.0), options);
  ASSERT_TRUE(loose.ok());
  EXPECT_FALSE(loose->suitable);
  EXPECT_TRUE(has(*loose, "POSITION_UNCERTAIN"));
  EXPECT_FALSE(has(*loose, "AMBIGUOUS_ROAD"));
  int unsuitable = 0;
  for (const auto id : loose->region->segment_ids) {
    if (!map.assess_segment(id, options)->suitable) ++unsuitable;
  }
  EXPECT_EQ(unsuitable, 1);
  // The first unsuitable place was found within 0.5 m, so the line across the road lies
  // between a = 0.5 and a = 1.0 standard deviations ahead.
  EXPECT_GE(loose->region->suitable_share, truncated_share(0.5, 0.95) - 0.01);
  EXPECT_LE(loose->region->suitable_share, truncated_share(1.0, 0.95) + 0.01);
}

}  // namespace
