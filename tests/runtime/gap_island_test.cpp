// Two-stage crossings at a refuge island: gap_decision, hcm_gap_decision and the simulator.
//
// The crossing of gap_test.cpp: the robot waits at (0, 0) and crosses north; the centreline at
// (0, 4), 6 m and 2 lanes: lane 0 = [1, 4], lane 1 = [4, 7] from the kerb. Robot 1 m/s, 1 s
// start-up, radius 0.5 m; corridor half-width 1 m; min PET 1 s; vehicles 4 m long (in the
// corridor within 3 m of the crossing line); unseen vehicle 16.667 m/s, sensor range 200 m.
// With an island the near stage crosses lane 0 only (lanes / 2 = 1), the far stage lane 1 from
// the island at (0, 4):
//   stage 1: lane 0 left at 1 + (4 + 0.5) / 1 = 5.5 s (the stage's crossing time);
//            unseen margin (200 - 1) / 16.667 - 5.5 = 6.44 s;
//   stage 2: from (0, 4) the near edge is at -3, lane 1 = [0, 3]: entered at once (0 s), left
//            at 1 + (3 + 0.5) / 1 = 4.5 s; unseen margin 11.94 - 4.5 = 7.44 s.
// Without an island lane 1 is left at 8.5 s (gap_test.cpp).
#include <gtest/gtest.h>

#include <vector>

#include "roadcross/gap.hpp"
#include "roadcross/simulate.hpp"

using namespace roadcross;

namespace {

GapCrossing crossing(bool island, int stage) {
  GapCrossing c;
  c.start = stage == 2 ? PlanePoint{0.0, 4.0} : PlanePoint{0.0, 0.0};
  c.centre = {0.0, 4.0};
  c.heading_rad = geo::kPi / 2;
  c.road_width_m = 6.0;
  c.lanes = 2;
  c.maxspeed_kmh = 50.0;
  c.refuge_island = island;
  c.stage = stage;
  return c;
}

GapOptions options() {
  GapOptions o;
  o.min_pet_s = 1.0;
  o.safety_buffer_m = 0.5;
  o.speed_uncertainty_fraction = 0.0;
  o.sensor_range_m = 200.0;
  return o;
}

TrackedVehicle car(double x, double y, double vx) {
  TrackedVehicle v;
  v.x_m = x, v.y_m = y, v.vx_mps = vx, v.length_m = 4.0;
  return v;
}

GapDecision decide(const GapCrossing& c, const std::vector<TrackedVehicle>& vehicles) {
  const auto r = gap_decision(c, RobotMotion{1.0, 1.0, 0.5}, vehicles, 0.0, options());
  EXPECT_TRUE(r.ok()) << r.status.message;
  return *r.value;
}

// Lane 1, 80 m east, 10 m/s west: in the corridor from (80 - 3) / 10 = 7.7 s to 8.3 s.
const TrackedVehicle kFarLaneCar = car(80.0, 5.5, -10.0);
// Lane 0, 30 m west, 10 m/s east: in the corridor from 2.7 s to 3.3 s.
const TrackedVehicle kNearLaneCar = car(-30.0, 2.5, 10.0);

TEST(GapIsland, WithoutAnIslandTheFarLaneCarStopsTheRobot) {
  // The robot is in lane 1 from 4.5 to 8.5 s: PET max(7.7 - 8.5, 4.5 - 8.3) = -0.8.
  const GapDecision d = decide(crossing(false, 1), {kFarLaneCar});
  EXPECT_EQ(d.stage, 0);
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_NEAR(*d.margin_s, -0.8, 1e-9);
  EXPECT_NEAR(d.crossing_time_s, 8.5, 1e-9);
}

TEST(GapIsland, StageOneCrossesTheNearLanesOnly) {
  const GapDecision d = decide(crossing(true, 1), {kFarLaneCar});
  EXPECT_EQ(d.stage, 1);
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_EQ(d.vehicles_counted, 0);
  EXPECT_NEAR(d.crossing_time_s, 5.5, 1e-9);
  EXPECT_NEAR(*d.margin_s, 199.0 / (50.0 / 3.6 * 1.2) - 5.5, 1e-9);  // the unseen vehicle
  // Required sight: 16.667 * (5.5 + 1) + 1 = 109.33 m (one stage: 159.33 m).
  EXPECT_NEAR(d.required_sight_m, 50.0 / 3.6 * 1.2 * 6.5 + 1.0, 1e-9);
  // A near-lane car 30 m away: the robot is in lane 0 from 1.5 to 5.5 s, the car from 2.7 to
  // 3.3 s: PET max(2.7 - 5.5, 1.5 - 3.3) = -1.8 -> WAIT.
  const GapDecision near = decide(crossing(true, 1), {kNearLaneCar, kFarLaneCar});
  EXPECT_EQ(near.verdict, GapVerdict::wait);
  EXPECT_NEAR(*near.margin_s, -1.8, 1e-9);
  EXPECT_EQ(near.limiting_vehicle, 0);
}

TEST(GapIsland, StageTwoStartsOnTheIsland) {
  // In lane 1 from 0 to 4.5 s; the far-lane car from 7.7 s: PET 7.7 - 4.5 = 3.2 -> GO. The
  // near-lane car is behind the robot now.
  const GapDecision d = decide(crossing(true, 2), {kNearLaneCar, kFarLaneCar});
  EXPECT_EQ(d.stage, 2);
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_EQ(d.vehicles_counted, 1);
  EXPECT_NEAR(d.crossing_time_s, 4.5, 1e-9);
  EXPECT_NEAR(*d.margin_s, 3.2, 1e-9);
  // The same car 40 m east: in 3.7 s, out 4.3 s: PET max(3.7 - 4.5, 0 - 4.3) = -0.8 -> WAIT.
  const GapDecision close = decide(crossing(true, 2), {car(40.0, 5.5, -10.0)});
  EXPECT_EQ(close.verdict, GapVerdict::wait);
  EXPECT_NEAR(*close.margin_s, -0.8, 1e-9);
}

TEST(GapIsland, HcmCriticalGapOfHalfTheRoad) {
  // t_c = 3 m / 1 m/s + 3 s = 6 s (one stage: 6 / 1 + 3 = 9 s).
  const auto d = hcm_gap_decision(crossing(true, 1), RobotMotion{1.0, 1.0, 0.5},
                                  std::vector{kFarLaneCar}, 0.0, options());
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(d->stage, 1);
  EXPECT_NEAR(d->critical_gap_s, 6.0, 1e-12);
  EXPECT_EQ(d->verdict, GapVerdict::go);  // the far-lane car is the other stage's
}

TEST(GapIsland, BadStagesAndOneLane) {
  GapCrossing c = crossing(true, 3);
  EXPECT_EQ(gap_decision(c, RobotMotion{}, nullptr, 0, 0.0).status.code,
            StatusCode::invalid_argument);
  c = crossing(true, 1);
  c.lanes = 1;  // no island fits a one-lane road: one stage
  EXPECT_EQ(decide(c, {}).stage, 0);
}

// The simulator's default road: 2 lanes, 7 m, the robot 0.5 m before the near edge, 1.2 m/s,
// 1 s start-up, radius 0.4 m. The island's centre is on the lane boundary, 0.5 + 3.5 = 4 m
// from the start; the far side is reached at 0.5 + 7 + 0.4 = 7.9 m.
TEST(SimulateIsland, EmptyRoadTwoStagesWalkOnAtOnce) {
  sim::Scenario s;
  s.volume_veh_h_per_lane = 0.0;
  s.road.refuge_island = true;
  const auto m = sim::simulate_run(s, 1);
  ASSERT_TRUE(m.ok());
  EXPECT_TRUE(m->crossed);
  EXPECT_EQ(m->decisions, 2);  // one at the kerb, one on the island
  EXPECT_DOUBLE_EQ(m->waiting_s, 0.0);
  EXPECT_DOUBLE_EQ(m->island_wait_s, 0.0);
  // (1 + 4 / 1.2) + (1 + 3.9 / 1.2) = 8.5833 s.
  EXPECT_NEAR(m->crossing_s, 2.0 + 7.9 / 1.2, 1e-12);
  EXPECT_EQ(m->acceptable_gaps_offered, 2);
  EXPECT_TRUE(m->used_acceptable_gap);
}

TEST(SimulateIsland, TheIslandNeedsLessSight) {
  // 100 m of sight. One stage needs 16.667 * (7.5833 + 1.2) + 0.9 = 147.29 m: ours gives up.
  // Stage 1 leaves lane 0 at 1 + 4.4 / 1.2 = 4.667 s: 16.667 * 5.867 + 0.9 = 98.68 m; stage 2
  // (near edge 3.5 m behind the island) leaves lane 1 at 1 + 3.9 / 1.2 = 4.25 s: 91.73 m.
  sim::Scenario s;
  s.volume_veh_h_per_lane = 0.0;
  s.road.sight_m = 100.0;
  s.max_wait_s = 5.0;
  EXPECT_FALSE(sim::simulate_run(s, 1)->crossed);
  s.road.refuge_island = true;
  EXPECT_TRUE(sim::simulate_run(s, 1)->crossed);
}

TEST(SimulateIsland, BusyRoadNoCollisionForOurs) {
  sim::Scenario s;
  s.volume_veh_h_per_lane = 500.0;
  s.road.refuge_island = true;
  const auto a = sim::simulate(s, 40, 7);
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->collisions, 0);
  EXPECT_GT(a->crossed, 0);
}

}  // namespace
