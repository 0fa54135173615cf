// gap_decision() and hcm_gap_decision() on single vehicles, with every number computed by hand.
//
// The crossing: the robot waits at (0, 0) and crosses north (heading pi/2); the centreline is at
// (0, 4), the road 6 m wide with 2 lanes, so across the road (distance d from the start):
//   near edge d = 1, lane 0 = [1, 4], lane 1 = [4, 7], far edge d = 7.
// Along the road: s = x (east), since the along-road axis is the heading turned clockwise.
// Robot: 1 m/s, 1 s start-up, radius 0.5 m. Lane occupation (start-up + (edge -+ radius) / speed):
//   lane 0: enter 1 + 0.5 = 1.5 s, leave 1 + 4.5 = 5.5 s;
//   lane 1: enter 1 + 3.5 = 4.5 s, leave 1 + 7.5 = 8.5 s  (= crossing time).
// Options: buffer 0.5 m -> corridor half-width c = 1.0 m; min PET 1 s; no speed uncertainty;
// sensor range 200 m. Vehicles 4 m long: a vehicle centre within c + 2 = 3 m of the crossing
// line is in the corridor. The unseen vehicle drives 50 / 3.6 * 1.2 = 16.667 m/s:
//   required sight = 16.667 * (8.5 + 1) + 1 = 159.33 m; its margin (200 - 1) / 16.667 - 8.5 = 3.44
//   s.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "roadcross/gap.hpp"

using namespace roadcross;

namespace {

GapCrossing crossing() {
  GapCrossing c;
  c.start = {0.0, 0.0};
  c.centre = {0.0, 4.0};
  c.heading_rad = geo::kPi / 2;
  c.road_width_m = 6.0;
  c.lanes = 2;
  c.maxspeed_kmh = 50.0;
  return c;
}

RobotMotion robot() {
  return RobotMotion{1.0, 1.0, 0.5};
}

GapOptions options() {
  GapOptions o;
  o.min_pet_s = 1.0;
  o.safety_buffer_m = 0.5;
  o.speed_uncertainty_fraction = 0.0;
  o.sensor_range_m = 200.0;
  return o;
}

TrackedVehicle car(double x, double y, double vx, double time_s = 0.0) {
  TrackedVehicle v;
  v.x_m = x, v.y_m = y, v.vx_mps = vx, v.vy_mps = 0.0, v.length_m = 4.0, v.time_s = time_s;
  return v;
}

GapDecision decide(const std::vector<TrackedVehicle>& vehicles, const GapOptions& o = options()) {
  const auto r = gap_decision(crossing(), robot(), vehicles, 0.0, o);
  EXPECT_TRUE(r.ok()) << r.status.message;
  return *r.value;
}

TEST(Gap, EmptyRoadIsGoLimitedByTheUnseenVehicle) {
  const GapDecision d = decide({});
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_EQ(d.reason, GapReason::clear);
  EXPECT_DOUBLE_EQ(d.crossing_time_s, 8.5);
  EXPECT_NEAR(d.required_sight_m, 50.0 / 3.6 * 1.2 * 9.5 + 1.0, 1e-9);  // 159.33
  EXPECT_NEAR(*d.margin_s, 199.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);     // 3.44
  EXPECT_EQ(d.limiting_vehicle, -1);
  EXPECT_DOUBLE_EQ(*d.earliest_start_s, 0.0);
}

TEST(Gap, ArrivesJustAfterTheRobotClearsItsLane) {
  // Lane 0, 70 m west, 10 m/s east: enters (70 - 3) / 10 = 6.7 s; the robot left at 5.5 s.
  const GapDecision d = decide({car(-70.0, 2.5, 10.0)});
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_NEAR(*d.margin_s, 1.2, 1e-9);
  EXPECT_EQ(d.limiting_vehicle, 0);
  EXPECT_EQ(d.vehicles_counted, 1);
}

TEST(Gap, ArrivesJustBeforeTheRobotClearsItsLane) {
  // 60 m west: enters (60 - 3) / 10 = 5.7 s, leaves (60 + 3) / 10 = 6.3 s. PET 5.7 - 5.5 = 0.2.
  // Forbidden starts: (5.7 - 1 - 5.5, 6.3 + 1 - 1.5) = (-0.8, 5.8): earliest start 5.8 s.
  const GapDecision d = decide({car(-60.0, 2.5, 10.0)});
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_EQ(d.reason, GapReason::vehicle_conflict);
  EXPECT_NEAR(*d.margin_s, 0.2, 1e-9);
  EXPECT_EQ(d.limiting_vehicle, 0);
  EXPECT_NEAR(*d.earliest_start_s, 5.8, 1e-9);
}

TEST(Gap, SpeedUncertaintyMakesTheJustAfterCaseWait) {
  // +-10 %: the earliest arrival uses 11 m/s: 67 / 11 = 6.0909 s, PET 0.5909 < 1.
  GapOptions o = options();
  o.speed_uncertainty_fraction = 0.1;
  const GapDecision d = decide({car(-70.0, 2.5, 10.0)}, o);
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_NEAR(*d.margin_s, 67.0 / 11.0 - 5.5, 1e-9);
}

TEST(Gap, OldObservationIsExtrapolatedToNow) {
  // Seen 0.3 s ago at 73 m west: now at 70 m, as in the just-after case.
  const auto r =
      gap_decision(crossing(), robot(), std::vector{car(-73.0, 2.5, 10.0, -0.3)}, 0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(*r->margin_s, 1.2, 1e-9);
  EXPECT_EQ(r->verdict, GapVerdict::go);
}

TEST(Gap, VehicleAlreadyPastDoesNotCount) {
  // 10 m east and driving east: it left the corridor (rear at 8 m > 1 m) before now.
  const GapDecision d = decide({car(10.0, 2.5, 10.0)});
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_EQ(d.vehicles_counted, 0);
  EXPECT_EQ(d.limiting_vehicle, -1);
}

TEST(Gap, StoppedVehicle) {
  // Stopped 20 m away: never arrives under the prediction -> GO.
  EXPECT_EQ(decide({car(-20.0, 2.5, 0.0)}).verdict, GapVerdict::go);
  // Stopped with its centre 2 m from the crossing line (< 3 m): it stands in the corridor.
  const GapDecision d = decide({car(-20.0, 2.5, 0.0), car(-2.0, 5.5, 0.0)});
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_EQ(d.reason, GapReason::blocked);
  EXPECT_EQ(d.limiting_vehicle, 1);
  EXPECT_FALSE(d.earliest_start_s.has_value());
}

TEST(Gap, TwoLanesOneVehicleInEachDirection) {
  // Lane 0: 100 m west, 10 m/s east: in 9.7 s, out 10.3 s; PET 9.7 - 5.5 = 4.2.
  // Lane 1: 80 m east, 10 m/s west: in 7.7 s, out 8.3 s; the robot is in lane 1 from 4.5 to
  // 8.5 s: PET max(7.7 - 8.5, 4.5 - 8.3) = -0.8 (they would meet).
  // Forbidden starts: lane 1 (7.7-1-8.5, 8.3+1-4.5) = (-1.8, 4.8); lane 0 (9.7-1-5.5,
  // 10.3+1-1.5) = (3.2, 9.8): after the first car, the second is in the way -> 9.8 s.
  const GapDecision d = decide({car(-100.0, 2.5, 10.0), car(80.0, 5.5, -10.0)});
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_NEAR(*d.margin_s, -0.8, 1e-9);
  EXPECT_EQ(d.limiting_vehicle, 1);
  EXPECT_NEAR(*d.earliest_start_s, 9.8, 1e-9);
  // The lane-1 car at 120 m instead: in 11.7 s, PET 11.7 - 8.5 = 3.2 -> GO, and 3.2 is the
  // smallest of 4.2, 3.2 and the unseen vehicle's 3.44.
  const GapDecision go = decide({car(-100.0, 2.5, 10.0), car(120.0, 5.5, -10.0)});
  EXPECT_EQ(go.verdict, GapVerdict::go);
  EXPECT_NEAR(*go.margin_s, 3.2, 1e-9);
  EXPECT_EQ(go.limiting_vehicle, 1);
}

TEST(Gap, PassingBehindAFarLaneVehicleIsGoButNotForHcm) {
  // Lane 1, 20 m east, 10 m/s west: in 1.7 s, out 2.3 s; the robot reaches lane 1 at 4.5 s:
  // PET 4.5 - 2.3 = 2.2 >= 1 -> GO.
  const std::vector vehicles{car(20.0, 5.5, -10.0)};
  const GapDecision ours = decide(vehicles);
  EXPECT_EQ(ours.verdict, GapVerdict::go);
  EXPECT_NEAR(*ours.margin_s, 2.2, 1e-9);
  // HCM: t_c = 6 / 1 + 3 = 9 s; the next vehicle arrives in 1.7 s: gap 1.7 - 9 = -7.3 -> WAIT,
  // until it has left at 2.3 s.
  const auto hcm = hcm_gap_decision(crossing(), robot(), vehicles, 0.0, options());
  ASSERT_TRUE(hcm.ok());
  EXPECT_DOUBLE_EQ(hcm->critical_gap_s, 9.0);
  EXPECT_EQ(hcm->verdict, GapVerdict::wait);
  EXPECT_EQ(hcm->reason, GapReason::gap_too_short);
  EXPECT_NEAR(*hcm->margin_s, -7.3, 1e-9);
  EXPECT_NEAR(*hcm->earliest_start_s, 2.3, 1e-9);
  // A lane-0 car arriving in (100 - 3) / 10 = 9.7 s >= 9 s: HCM goes, margin 0.7 s.
  const auto hcm_go =
      hcm_gap_decision(crossing(), robot(), std::vector{car(-100.0, 2.5, 10.0)}, 0.0, options());
  EXPECT_EQ(hcm_go->verdict, GapVerdict::go);
  EXPECT_NEAR(*hcm_go->margin_s, 0.7, 1e-9);
}

TEST(Gap, HcmCriticalGapFormula) {
  // 7.5 m at 1.2 m/s plus 3 s: 6.25 + 3 = 9.25 s.
  EXPECT_DOUBLE_EQ(hcm_critical_gap_s(7.5, 1.2, 3.0), 9.25);
}

TEST(Gap, ShortSensorRangeIsInsufficientSight) {
  // 150 m < 159.33 m needed for an unseen 60 km/h car in the far lane.
  GapOptions o = options();
  o.sensor_range_m = 150.0;
  const GapDecision d = decide({}, o);
  EXPECT_EQ(d.verdict, GapVerdict::wait);
  EXPECT_EQ(d.reason, GapReason::insufficient_sight);
  EXPECT_FALSE(d.earliest_start_s.has_value());
  EXPECT_NEAR(*d.margin_s, 149.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);  // 0.44 s < 1 s
}

TEST(Gap, SightDistanceFromTheDbCutsTheVisibleRoad) {
  // The DB sees 300 m forward but only 150 m backward (a building beside a bend): the unseen
  // car can hide 150 m away although the sensor reaches 200 m. 150 m < 159.33 m -> WAIT.
  GapCrossing c = crossing();
  c.sight_forward_m = 300.0;
  c.sight_backward_m = 150.0;
  auto r = gap_decision(c, robot(), {}, 0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->reason, GapReason::insufficient_sight);
  EXPECT_DOUBLE_EQ(r->visible_road_m, 150.0);
  EXPECT_NEAR(*r->margin_s, 149.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);  // 0.44 s
  // 170 m backward: (170 - 1) / 16.667 - 8.5 = 1.64 s >= 1 -> GO.
  c.sight_backward_m = 170.0;
  r = gap_decision(c, robot(), {}, 0.0, options());
  EXPECT_EQ(r->verdict, GapVerdict::go);
  EXPECT_NEAR(*r->margin_s, 169.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);
  // Both beyond the sensor range: the range limits (the empty-road case, 3.44 s).
  c.sight_forward_m = c.sight_backward_m = 300.0;
  r = gap_decision(c, robot(), {}, 0.0, options());
  EXPECT_DOUBLE_EQ(r->visible_road_m, 200.0);
  EXPECT_NEAR(*r->margin_s, 199.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);
  // A junction 180 m away lies beyond a 170 m view: the hidden-car rule already covers it.
  c.sight_backward_m = 170.0;
  c.junction_distance_m = 180.0;
  r = gap_decision(c, robot(), {}, 0.0, options());
  EXPECT_NEAR(*r->margin_s, 169.0 / (50.0 / 3.6 * 1.2) - 8.5, 1e-9);
}

TEST(Gap, TrackBeyondSensorRangeIsCountedAndReported) {
  // 300 m west at 10 m/s: in 29.7 s, harmless, but reported as beyond the 200 m range.
  const GapDecision d = decide({car(-300.0, 2.5, 10.0)});
  EXPECT_EQ(d.verdict, GapVerdict::go);
  EXPECT_EQ(d.beyond_sensor_range, 1);
  EXPECT_EQ(d.vehicles_counted, 1);
}

TEST(Gap, StaleTrackMeansWait) {
  // Seen 1 s ago (> 0.5 s), even though it would be harmless.
  const auto r = gap_decision(crossing(), robot(),
                              std::vector{car(-300.0, 2.5, 10.0), car(-400.0, 2.5, 10.0, -1.0)},
                              0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->verdict, GapVerdict::wait);
  EXPECT_EQ(r->reason, GapReason::stale_track);
  EXPECT_EQ(r->limiting_vehicle, 1);
  EXPECT_EQ(r->stale_tracks, 1);
  EXPECT_FALSE(r->earliest_start_s.has_value());
}

TEST(Gap, VehicleInRobotEnuFrameIsRotatedByConvergence) {
  // Grid = ENU rotated by -convergence. Give the just-after car in ENU, rotated by +0.1 rad:
  // the decision must match the grid case (PET 1.2 s).
  GapCrossing c = crossing();
  c.convergence_rad = 0.1;
  TrackedVehicle v = car(0, 0, 0);
  v.frame = TrackedVehicle::Frame::robot_enu;
  v.x_m = -70.0 * std::cos(0.1) - 2.5 * std::sin(0.1);
  v.y_m = -70.0 * std::sin(0.1) + 2.5 * std::cos(0.1);
  v.vx_mps = 10.0 * std::cos(0.1);
  v.vy_mps = 10.0 * std::sin(0.1);
  const auto r = gap_decision(c, robot(), std::vector{v}, 0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(*r->margin_s, 1.2, 1e-9);
}

TEST(Gap, AnUncertainFixWidensTheCorridorForGridTracksOnly) {
  // The just-after car (PET 1.2 s) with the robot's fix uncertain by 1.5 m along the road: the
  // grid-tracked car may be 1.5 m nearer, so it enters at (70 - 3 - 1.5) / 10 = 6.55 s: PET
  // 1.05 s, still GO at min PET 1 s; 4 m makes it 6.3 s: PET 0.8 s, WAIT. Tracked relative to the robot
  // (robot_enu) the same car is unaffected: PET 1.2 s.
  GapCrossing c = crossing();
  c.along_road_uncertainty_m = 1.5;
  auto r = gap_decision(c, robot(), std::vector{car(-70.0, 2.5, 10.0)}, 0.0, options());
  ASSERT_TRUE(r.ok()) << r.status.message;
  EXPECT_NEAR(*r->margin_s, 1.05, 1e-9);
  EXPECT_EQ(r->verdict, GapVerdict::go);
  c.along_road_uncertainty_m = 4.0;
  r = gap_decision(c, robot(), std::vector{car(-70.0, 2.5, 10.0)}, 0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(*r->margin_s, 0.8, 1e-9);
  EXPECT_EQ(r->verdict, GapVerdict::wait);
  TrackedVehicle relative = car(-70.0, 2.5, 10.0);
  relative.frame = TrackedVehicle::Frame::robot_enu;
  r = gap_decision(c, robot(), std::vector{relative}, 0.0, options());
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(*r->margin_s, 1.2, 1e-9);
  c.along_road_uncertainty_m = -1.0;
  EXPECT_EQ(gap_decision(c, robot(), {}, 0.0, options()).status.code,
            StatusCode::invalid_argument);
}

TEST(Gap, SightDistanceFromBend) {
  Assessment a;
  EXPECT_DOUBLE_EQ(sight_distance_m(a, 150.0), 150.0);
  a.radius_m = 50.0;  // sqrt(8 * 50 * 3) = 34.64 m
  EXPECT_NEAR(sight_distance_m(a, 150.0), std::sqrt(1200.0), 1e-9);
  a.junction_distance_m = 20.0;  // a junction does not block the view
  EXPECT_NEAR(sight_distance_m(a, 150.0), std::sqrt(1200.0), 1e-9);
}

TEST(Gap, SightDistanceFromTheDbReplacesTheBendEstimate) {
  Assessment a;
  a.radius_m = 50.0;  // the bend estimate would be 34.64 m
  a.sight_min_m = 80.0;
  EXPECT_DOUBLE_EQ(sight_distance_m(a, 150.0), 80.0);
  a.sight_min_m = 300.0;  // the sensor range still caps it
  EXPECT_DOUBLE_EQ(sight_distance_m(a, 150.0), 150.0);
}

TEST(Gap, JunctionCloseByMeansAVehicleCanTurnInUnseen) {
  // Turning in at 25 / 3.6 * 1.2 = 8.333 m/s. Junction 90 m away: (90 - 1) / 8.333 - 8.5 =
  // 2.18 s >= 1 -> GO (the range's 3.44 s is not smaller). Junction 80 m away:
  // (80 - 1) / 8.333 - 8.5 = 0.98 s < 1 -> WAIT, INSUFFICIENT_SIGHT.
  GapCrossing c = crossing();
  c.junction_distance_m = 90.0;
  auto r = gap_decision(c, robot(), {}, 0.0, options());
  EXPECT_EQ(r->verdict, GapVerdict::go);
  EXPECT_NEAR(*r->margin_s, 89.0 / (25.0 / 3.6 * 1.2) - 8.5, 1e-9);
  c.junction_distance_m = 80.0;
  r = gap_decision(c, robot(), {}, 0.0, options());
  EXPECT_EQ(r->reason, GapReason::insufficient_sight);
  EXPECT_NEAR(*r->margin_s, 79.0 / (25.0 / 3.6 * 1.2) - 8.5, 1e-9);
  // A junction beyond the sensor range is covered by the range rule.
  c.junction_distance_m = 250.0;
  EXPECT_EQ(gap_decision(c, robot(), {}, 0.0, options())->verdict, GapVerdict::go);
}

TEST(Gap, BadInputIsAnError) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto code = [](const GapCrossing& c, const RobotMotion& r, std::vector<TrackedVehicle> v) {
    return gap_decision(c, r, v, 0.0, options()).status.code;
  };
  GapCrossing blind = crossing();
  blind.sight_backward_m = -1.0;
  EXPECT_EQ(code(blind, robot(), {}), StatusCode::invalid_argument);
  blind.sight_backward_m = nan;
  EXPECT_EQ(code(blind, robot(), {}), StatusCode::invalid_argument);
  TrackedVehicle bad = car(-50.0, 2.5, 10.0);
  bad.vx_mps = nan;
  EXPECT_EQ(code(crossing(), robot(), {bad}), StatusCode::invalid_argument);
  RobotMotion backwards = robot();
  backwards.speed_mps = -1.0;
  EXPECT_EQ(code(crossing(), backwards, {}), StatusCode::invalid_argument);
  TrackedVehicle future = car(-50.0, 2.5, 10.0, 0.5);  // observed 0.5 s after now
  const auto r = gap_decision(crossing(), robot(), std::vector{future}, 0.0, options());
  EXPECT_EQ(r.status.code, StatusCode::invalid_argument);
  EXPECT_NE(r.status.message.find("future"), std::string::npos) << r.status.message;
  TrackedVehicle negative = car(-50.0, 2.5, 10.0);
  negative.speed_uncertainty_mps = -1.0;
  EXPECT_EQ(code(crossing(), robot(), {negative}), StatusCode::invalid_argument);
  negative = car(-50.0, 2.5, 10.0);
  negative.length_m = 0.0;
  EXPECT_EQ(code(crossing(), robot(), {negative}), StatusCode::invalid_argument);
  GapCrossing no_lanes = crossing();
  no_lanes.lanes = 0;
  EXPECT_EQ(code(no_lanes, robot(), {}), StatusCode::invalid_argument);
  EXPECT_EQ(hcm_gap_decision(crossing(), backwards, {}, 0.0).status.code,
            StatusCode::invalid_argument);
}

}  // namespace
