// monitor() on synthetic trajectories with values computed by hand. The plan crosses from
// (0, 0) north to (0, 10): heading pi/2, length 10 m.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "roadcross/monitor.hpp"

using roadcross::CrossingPlan;
using roadcross::CrossingState;
using roadcross::Pose;
using roadcross::geo::kPi;

namespace {

const CrossingPlan kPlan{{0.0, 0.0}, {0.0, 10.0}, kPi / 2, 6.0};

roadcross::CrossingProgress at(double x, double y, double yaw) {
  const auto r = roadcross::monitor(kPlan, Pose{{x, y}, yaw});
  EXPECT_TRUE(r.ok()) << r.status.message;
  return *r.value;
}

TEST(Monitor, StraightCrossingIsOnTrackThenDone) {
  for (double y = 0.0; y < 9.8; y += 0.5) {
    const auto p = at(0.0, y, kPi / 2);
    EXPECT_NEAR(p.progress, y / 10.0, 1e-12);
    EXPECT_NEAR(p.lateral_deviation_m, 0.0, 1e-12);
    EXPECT_EQ(p.state, CrossingState::on_track) << y;
  }
  EXPECT_EQ(at(0.0, 9.85, kPi / 2).state, CrossingState::done);  // within 0.2 m of the target
  const auto beyond = at(0.0, 12.0, kPi / 2);                    // overshoot: still done,
  EXPECT_EQ(beyond.state, CrossingState::done);                  // progress clamped to 1
  EXPECT_DOUBLE_EQ(beyond.progress, 1.0);
}

TEST(Monitor, DriftingSidewaysAndTurning) {
  // 0.3 m to the east of the line (right of north): lateral -0.3, still on track.
  EXPECT_NEAR(at(0.3, 5.0, kPi / 2).lateral_deviation_m, -0.3, 1e-12);
  EXPECT_EQ(at(0.3, 5.0, kPi / 2).state, CrossingState::on_track);
  // 0.8 m west: lateral +0.8 > 0.5 -> DRIFTING.
  const auto west = at(-0.8, 5.0, kPi / 2);
  EXPECT_NEAR(west.lateral_deviation_m, 0.8, 1e-12);
  EXPECT_EQ(west.state, CrossingState::drifting);
  // On the line but facing 30 degrees off: heading error 0.5236 > 0.35 -> DRIFTING.
  const auto turned = at(0.0, 5.0, kPi / 2 + kPi / 6);
  EXPECT_NEAR(turned.heading_error_rad, kPi / 6, 1e-12);
  EXPECT_EQ(turned.state, CrossingState::drifting);
  // Yaw given as -3pi/2 is the same as pi/2: no heading error.
  EXPECT_NEAR(at(0.0, 5.0, -3 * kPi / 2).heading_error_rad, 0.0, 1e-12);
  // 2 m east: outside the 1.5 m corridor, even if the progress is near the end.
  EXPECT_EQ(at(2.0, 5.0, kPi / 2).state, CrossingState::leaving_corridor);
  EXPECT_EQ(at(2.0, 9.9, kPi / 2).state, CrossingState::leaving_corridor);
}

TEST(Monitor, BadInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(roadcross::monitor(kPlan, Pose{{nan, 0.0}, 0.0}).status.code,
            roadcross::StatusCode::invalid_argument);
  EXPECT_EQ(roadcross::monitor(kPlan, Pose{{0.0, 0.0}, nan}).status.code,
            roadcross::StatusCode::invalid_argument);
  const CrossingPlan point{{1.0, 1.0}, {1.0, 1.0}, 0.0, 6.0};
  EXPECT_EQ(roadcross::monitor(point, Pose{{0.0, 0.0}, 0.0}).status.code,
            roadcross::StatusCode::invalid_argument);
  roadcross::MonitorOptions bad;
  bad.drift_m = -1.0;
  EXPECT_EQ(roadcross::monitor(kPlan, Pose{{0.0, 0.0}, 0.0}, bad).status.code,
            roadcross::StatusCode::invalid_argument);
}

}  // namespace
