// Map::assess on hand-made maps with known answers. The quiet road: a 600 m straight residential
// way in Czechia with no tags but the class, so every context input takes its documented default
// (docs/cost-model.md, "Context score"): CZ urban speed 50 km/h -> 2 points, 2 lanes -> 4,
// width 2 x 3.0 m = 6.0 m (<= 6.5) -> 1, residential (minor) -> 3: context 10. Its middle is
// straight and far from any junction: curvature cost 0, class cost 2, no elevation ->
// rank floor(15 * (0 + 5 * 2/5) / 75) = floor(0.4) = 0, score 15. 15 + 10 = 25 >= 20: suitable.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
using roadcross::Map;
using roadcross::Position;

namespace {

class Assess : public ::testing::Test {
 protected:
  void SetUp() override {
    // Residential: 50.0 N, 14.40 .. 14.4083 E (about 600 m). Motorway 300 m north of it.
    // A tunnel 300 m south.
    const std::string osm = dir_.write(
        "map.osm",
        rt::osm_document(rt::osm_node(1, 50.0, 14.40) + rt::osm_node(2, 50.0, 14.4083) +
                         rt::osm_node(3, 50.0027, 14.40) + rt::osm_node(4, 50.0027, 14.4083) +
                         rt::osm_node(5, 49.9973, 14.40) + rt::osm_node(6, 49.9973, 14.4083) +
                         rt::osm_way(10, "1 2", "highway=residential") +
                         rt::osm_way(20, "3 4", "highway=motorway") +
                         rt::osm_way(30, "5 6", "highway=residential;tunnel=yes")));
    db_ = dir_.file("map.gpkg");
    rp::BuildOptions options;
    options.osm_path = osm;
    options.output_path = db_;
    rp::run_build(options);
    auto map = Map::open(db_);
    ASSERT_TRUE(map.ok()) << map.status.message;
    map_.emplace(std::move(*map.value));
  }

  /// A point `north_m` north of the middle of the way at latitude `lat`.
  Position beside(double lat, double north_m) {
    const auto p = map_->to_utm(Position::wgs84(lat, 14.40415));
    return Position::utm(p->easting_m, p->northing_m + north_m);
  }

  static bool has(const roadcross::Assessment& a, const std::string& code) {
    return std::find(a.reasons.begin(), a.reasons.end(), code) != a.reasons.end();
  }

  rt::TempDir dir_;
  std::string db_;
  std::optional<Map> map_;
};

TEST_F(Assess, ThreeMetresOffAQuietStraightRoadIsSuitable) {
  const auto a = map_->assess(beside(50.0, 3.0));
  ASSERT_TRUE(a.ok()) << a.status.message;
  EXPECT_TRUE(a->valid);
  EXPECT_NEAR(a->road.distance_m, 3.0, 0.05);
  EXPECT_EQ(a->road.osm_way_id, 10);
  EXPECT_EQ(*a->rank, 0);
  EXPECT_EQ(*a->score, 15);
  EXPECT_EQ(*a->context_score, 10);
  EXPECT_EQ(*a->class_cost, 2);
  EXPECT_EQ(*a->curvature_cost, 0);
  EXPECT_DOUBLE_EQ(a->threshold, 20.0);  // recorded by the build
  EXPECT_DOUBLE_EQ(a->valid_distance_m, 10.0);
  EXPECT_TRUE(a->suitable);
  EXPECT_TRUE(has(*a, "NO_ELEVATION"));  // informative: no DEM was given
  EXPECT_FALSE(has(*a, "LOW_SCORE"));
}

TEST_F(Assess, ThirtyMetresAwayIsNotValid) {
  const auto a = map_->assess(beside(50.0, 30.0));
  ASSERT_TRUE(a.ok());
  EXPECT_FALSE(a->valid);
  EXPECT_FALSE(a->suitable);
  EXPECT_EQ(a->reasons.front(), "TOO_FAR_FROM_ROAD");
  // The same place with a 40 m validity radius given per call is valid again.
  roadcross::AssessOptions wide;
  wide.valid_distance_m = 40.0;
  const auto b = map_->assess(beside(50.0, 30.0), wide);
  EXPECT_TRUE(b->valid);
  EXPECT_TRUE(b->suitable);
}

TEST_F(Assess, ThresholdCanBeOverriddenPerCall) {
  roadcross::AssessOptions strict;
  strict.threshold = 26.0;  // 25 < 26
  const auto a = map_->assess(beside(50.0, 3.0), strict);
  EXPECT_FALSE(a->suitable);
  EXPECT_TRUE(has(*a, "LOW_SCORE"));
}

TEST_F(Assess, MotorwayAndTunnelAreNeverSuitable) {
  roadcross::AssessOptions anything;
  anything.threshold = -1000.0;
  const auto motorway = map_->assess(beside(50.0027, 3.0), anything);
  ASSERT_TRUE(motorway.ok());
  EXPECT_EQ(motorway->road.highway, "motorway");
  EXPECT_TRUE(motorway->valid);
  EXPECT_FALSE(motorway->suitable);
  EXPECT_TRUE(has(*motorway, "NOT_CROSSABLE_CLASS"));
  const auto tunnel = map_->assess(beside(49.9973, 3.0), anything);
  EXPECT_TRUE(tunnel->tunnel);
  EXPECT_FALSE(tunnel->suitable);
  EXPECT_TRUE(has(*tunnel, "TUNNEL"));
}

// The judgement render/export/view colour with: assess's answer on the centreline, for every
// segment of the map (quiet road suitable, motorway and tunnel not), and not_found for no fid.
TEST_F(Assess, AssessSegmentIsAssessOnTheCentreline) {
  int suitable = 0, segments = 0;
  for (std::int64_t fid = 1;; ++fid) {
    const auto by_id = map_->assess_segment(fid);
    if (by_id.status.code == roadcross::StatusCode::not_found) break;
    ASSERT_TRUE(by_id.ok()) << by_id.status.message;
    ++segments;
    EXPECT_TRUE(by_id->valid);
    EXPECT_DOUBLE_EQ(by_id->road.distance_m, 0.0);
    EXPECT_EQ(by_id->road.segment_id, fid);
    suitable += by_id->suitable ? 1 : 0;
    if (by_id->road.highway == "motorway" || by_id->tunnel) {
      EXPECT_FALSE(by_id->suitable);
    }
  }
  EXPECT_GT(segments, 3);
  EXPECT_GT(suitable, 0);
  // At the quiet road's middle, 3 m off: the nearest segment's verdict is assess's verdict.
  const auto a = map_->assess(beside(50.0, 3.0));
  const auto b = map_->assess_segment(a->road.segment_id);
  EXPECT_EQ(a->suitable, b->suitable);
  EXPECT_EQ(a->reasons, b->reasons);
  EXPECT_EQ(a->road.highway, b->road.highway);
  // 30 m off: not valid, TOO_FAR_FROM_ROAD in front of the segment's own reasons.
  const auto far = map_->assess(beside(50.0, 30.0));
  std::vector<std::string> expected = {"TOO_FAR_FROM_ROAD"};
  const auto far_segment = map_->assess_segment(far->road.segment_id);
  expected.insert(expected.end(), far_segment->reasons.begin(), far_segment->reasons.end());
  EXPECT_EQ(far->reasons, expected);
  EXPECT_TRUE(far_segment->suitable);
  EXPECT_FALSE(far->suitable);
  EXPECT_EQ(map_->assess_segment(999999).status.code, roadcross::StatusCode::not_found);
}

TEST_F(Assess, ErrorsPassThrough) {
  EXPECT_EQ(map_->assess(Position::wgs84(95.0, 14.4)).status.code,
            roadcross::StatusCode::invalid_argument);
  roadcross::AssessOptions near_only;
  near_only.max_distance_m = 5.0;
  EXPECT_EQ(map_->assess(beside(50.0, 100.0), near_only).status.code,
            roadcross::StatusCode::not_found);
}

}  // namespace

namespace {

// A T junction: main residential road along 50.0 N from 14.40 to 14.4166 E (~1.2 km), a side
// road going north from its middle node 2 (14.4083 E). Node 2 has degree 3.
class BetterPlace : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string osm = dir_.write(
        "t.osm",
        rt::osm_document(rt::osm_node(1, 50.0, 14.40) + rt::osm_node(2, 50.0, 14.4083) +
                         rt::osm_node(3, 50.0, 14.4166) + rt::osm_node(4, 50.003, 14.4083) +
                         rt::osm_way(10, "1 2 3", "highway=residential") +
                         rt::osm_way(20, "2 4", "highway=residential")));
    rp::BuildOptions options;
    options.osm_path = osm;
    options.output_path = dir_.file("t.gpkg");
    rp::run_build(options);
    auto map = Map::open(dir_.file("t.gpkg"));
    ASSERT_TRUE(map.ok());
    map_.emplace(std::move(*map.value));
    junction_ = *map_->to_utm(Position::wgs84(50.0, 14.4083));
  }
  rt::TempDir dir_;
  std::optional<Map> map_;
  roadcross::PlanePoint junction_;
};

TEST_F(BetterPlace, NextToAJunctionTheBetterPlaceIsAwayFromItOnTheSameSide) {
  // 8 m west of the junction, 3 m south of the main road (the side without the side road).
  const Position robot = Position::utm(junction_.easting_m - 8.0, junction_.northing_m - 3.0);
  const auto here = map_->assess(robot);
  ASSERT_TRUE(here.ok());
  EXPECT_TRUE(std::find(here->reasons.begin(), here->reasons.end(), "NEAR_JUNCTION") !=
              here->reasons.end());
  const auto places = map_->better_place(robot);
  ASSERT_TRUE(places.ok()) << places.status.message;
  ASSERT_FALSE(places->candidates.empty()) << places->reason;
  const roadcross::Candidate& best = places->candidates.front();
  EXPECT_TRUE(best.suitable);
  // No candidate is within the 15 m junction zone, and every one is within the radius.
  for (const auto& c : places->candidates) {
    EXPECT_GE(std::hypot(c.point.easting_m - junction_.easting_m,
                         c.point.northing_m - junction_.northing_m),
              15.0);
    EXPECT_LE(c.walking_distance_m, 100.0);
  }
  // Same side (south of the main road, at the robot's 3 m offset): the road runs along 50.0 N,
  // so its northing there is within ~1 m of the junction's (grid convergence over < 100 m).
  // No candidate is on the side road to the north: reaching it would mean crossing.
  for (const auto& c : places->candidates) {
    EXPECT_LT(c.point.northing_m, junction_.northing_m - 2.0);
    EXPECT_GT(c.point.northing_m, junction_.northing_m - 4.0);
    EXPECT_NEAR(c.crossing_heading_rad, roadcross::geo::kPi / 2, 0.05);  // cross northwards
  }
  EXPECT_GE(best.walking_distance_m, 15.0);
  // Ranked: suitable first, then score, then walking distance.
  for (std::size_t i = 1; i < places->candidates.size(); ++i) {
    const auto& a = places->candidates[i - 1];
    const auto& b = places->candidates[i];
    EXPECT_TRUE(a.suitable >= b.suitable);
    if (a.suitable == b.suitable && a.designated_crossing == b.designated_crossing) {
      EXPECT_GE(a.score, b.score);
    }
  }
}

TEST_F(BetterPlace, ASideRoadOnTheRobotsOwnSideCanBeReached) {
  // 8 m west of the junction, 3 m NORTH of the main road: the side road (north) is on the
  // robot's side, so walking into it needs no crossing; with 60 m of search the side road's
  // segments beyond its junction zone (15..60 m up it) are among the reachable places.
  roadcross::BetterPlaceOptions options;
  options.search_radius_m = 60.0;
  options.max_candidates = 50;
  // Reachability, not the costs: with threshold 0 every reached place is suitable and listed
  // (the 20 m junction reach leaves the short side road below the default threshold).
  options.assess.threshold = 0.0;
  const auto places = map_->better_place(
      Position::utm(junction_.easting_m - 8.0, junction_.northing_m + 3.0), options);
  ASSERT_TRUE(places.ok());
  const bool on_side_road =
      std::any_of(places->candidates.begin(), places->candidates.end(),
                  [&](const auto& c) { return c.point.northing_m > junction_.northing_m + 15.0; });
  EXPECT_TRUE(on_side_road);
  // ... and none is south of the main road.
  for (const auto& c : places->candidates) EXPECT_GT(c.point.northing_m, junction_.northing_m);
}

TEST_F(BetterPlace, NothingSuitableGivesAnEmptyListWithAReason) {
  roadcross::BetterPlaceOptions impossible;
  impossible.assess.threshold = 1000.0;
  const auto places = map_->better_place(
      Position::utm(junction_.easting_m - 50.0, junction_.northing_m - 3.0), impossible);
  ASSERT_TRUE(places.ok());
  EXPECT_TRUE(places->candidates.empty());
  EXPECT_NE(places->reason.find("no suitable place"), std::string::npos);
  roadcross::BetterPlaceOptions bad;
  bad.search_radius_m = 0.0;
  EXPECT_EQ(
      map_->better_place(Position::utm(junction_.easting_m, junction_.northing_m), bad).status.code,
      roadcross::StatusCode::invalid_argument);
}

}  // namespace

#include "roadcross/monitor.hpp"

namespace {

TEST_F(Assess, PlanCrossingAimsAtTheFarSideAndMonitorFollowsIt) {
  // 3 m south of the quiet road (width 6.0 m by default from 2 lanes x 3.0 m): the plan goes
  // north, to 6.0 / 2 + 0.5 = 3.5 m beyond the centreline.
  const auto plan = roadcross::plan_crossing(*map_, beside(50.0, -3.0));
  ASSERT_TRUE(plan.ok()) << plan.status.message;
  EXPECT_DOUBLE_EQ(plan->road_width_m, 6.0);
  EXPECT_NEAR(plan->heading_rad, roadcross::geo::kPi / 2, 0.01);
  EXPECT_NEAR(std::hypot(plan->target.easting_m - plan->start.easting_m,
                         plan->target.northing_m - plan->start.northing_m),
              3.0 + 3.5, 0.01);
  const auto halfway = roadcross::monitor(
      *plan, roadcross::Pose{{0.5 * (plan->start.easting_m + plan->target.easting_m),
                              0.5 * (plan->start.northing_m + plan->target.northing_m)},
                             plan->heading_rad});
  ASSERT_TRUE(halfway.ok());
  EXPECT_NEAR(halfway->progress, 0.5, 1e-9);
  EXPECT_EQ(halfway->state, roadcross::CrossingState::on_track);
}

}  // namespace

#include <thread>

namespace {

TEST_F(Assess, ConcurrentMapsGiveTheSameAnswers) {
  // One Map per thread (the documented model); four threads answer the same 200 queries as a
  // single thread did, with no shared state between them.
  std::vector<Position> queries;
  for (int i = 0; i < 200; ++i) queries.push_back(beside(50.0, -40.0 + 0.4 * i));
  std::vector<std::pair<bool, std::int64_t>> expected;
  for (const Position& q : queries) {
    const auto a = map_->assess(q);
    expected.emplace_back(a.ok() && a->suitable, a.ok() ? a->road.segment_id : -1);
  }
  std::vector<int> mismatches(4, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&, t] {
      auto own = Map::open(db_);
      for (int round = 0; round < 5; ++round) {
        for (std::size_t i = 0; i < queries.size(); ++i) {
          const auto a = own->assess(queries[i]);
          const std::pair<bool, std::int64_t> got{a.ok() && a->suitable,
                                                  a.ok() ? a->road.segment_id : -1};
          if (got != expected[i]) ++mismatches[static_cast<std::size_t>(t)];
        }
      }
    });
  }
  for (auto& thread : threads) thread.join();
  for (int m : mismatches) EXPECT_EQ(m, 0);
  // Both suitable and unsuitable answers were exercised.
  EXPECT_TRUE(std::any_of(expected.begin(), expected.end(), [](const auto& e) { return e.first; }));
  EXPECT_TRUE(
      std::any_of(expected.begin(), expected.end(), [](const auto& e) { return !e.first; }));
}

}  // namespace
