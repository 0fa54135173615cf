// The crossing simulator: hand-computed runs on an empty road, determinism for a seed, and the
// safety ordering of the policies on busy traffic.
//
// Default scenario: 2 lanes, 7 m, 50 km/h; the robot waits 0.5 m before the near edge, crosses
// at 1.2 m/s after 1 s, radius 0.4 m: it is clear of the far edge after
//   1 + (0.5 + 7 + 0.4) / 1.2 = 7.5833 s.
// Our policy needs, for an unseen car at 50 / 3.6 * 1.2 = 16.667 m/s in the far lane (left at
// 7.5833 s), with a 1.2 s margin and a 0.4 + 0.5 m corridor half-width:
//   16.667 * (7.5833 + 1.2) + 0.9 = 147.29 m of sight.
#include <gtest/gtest.h>

#include "roadcross/simulate.hpp"

using namespace roadcross;

namespace {

sim::RunMetrics run(const sim::Scenario& s, std::uint64_t seed = 1) {
  const auto r = sim::simulate_run(s, seed);
  EXPECT_TRUE(r.ok()) << r.status.message;
  return *r.value;
}

TEST(Simulate, EmptyRoadEveryPolicyGoesAtOnce) {
  for (sim::Policy p : {sim::Policy::ours, sim::Policy::hcm, sim::Policy::naive}) {
    sim::Scenario s;
    s.volume_veh_h_per_lane = 0.0;
    s.policy = p;
    const sim::RunMetrics m = run(s);
    EXPECT_TRUE(m.crossed) << sim::to_string(p);
    EXPECT_DOUBLE_EQ(m.waiting_s, 0.0);
    EXPECT_EQ(m.decisions, 1);
    EXPECT_NEAR(m.crossing_s, 1.0 + 7.9 / 1.2, 1e-12);
    EXPECT_FALSE(m.min_pet_s.has_value());
    EXPECT_FALSE(m.conflict);
    EXPECT_EQ(m.acceptable_gaps_offered, 1);
    EXPECT_TRUE(m.used_acceptable_gap);
  }
}

TEST(Simulate, ShortSightOursWaitsUntilItGivesUp) {
  // 100 m < 147.29 m: ours never goes; it decides every 0.1 s for 5 s = 50 times.
  sim::Scenario s;
  s.volume_veh_h_per_lane = 0.0;
  s.road.sight_m = 100.0;
  s.max_wait_s = 5.0;
  const sim::RunMetrics m = run(s);
  EXPECT_FALSE(m.crossed);
  EXPECT_DOUBLE_EQ(m.waiting_s, 5.0);
  EXPECT_EQ(m.decisions, 50);
  EXPECT_EQ(m.acceptable_gaps_offered, 1);  // the empty road was acceptable all along
  EXPECT_FALSE(m.used_acceptable_gap);
  // The naive rule does not look at sight: it goes at once.
  s.policy = sim::Policy::naive;
  EXPECT_TRUE(run(s).crossed);
}

TEST(Simulate, SameSeedSameNumbers) {
  sim::Scenario s;
  s.volume_veh_h_per_lane = 600.0;
  const auto a = sim::simulate(s, 20, 7), b = sim::simulate(s, 20, 7), c = sim::simulate(s, 20, 8);
  ASSERT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(a->mean_wait_s, b->mean_wait_s);
  EXPECT_EQ(a->p95_wait_s, b->p95_wait_s);
  EXPECT_EQ(a->min_pet_s, b->min_pet_s);
  EXPECT_EQ(a->acceptable_gap_share, b->acceptable_gap_share);
  EXPECT_EQ(a->conflicts, b->conflicts);
  EXPECT_NE(a->mean_wait_s, c->mean_wait_s);  // and the seed matters
}

TEST(Simulate, BusyRoadOursIsSafeNaiveShortDistanceIsNot) {
  sim::Scenario s;
  s.volume_veh_h_per_lane = 600.0;
  const auto ours = sim::simulate(s, 100, 3);
  s.policy = sim::Policy::naive;
  s.naive_distance_m = 30.0;  // 2.2 s at 50 km/h, for a 7.6 s crossing
  const auto naive = sim::simulate(s, 100, 3);
  ASSERT_TRUE(ours.ok() && naive.ok());
  EXPECT_EQ(ours->collisions, 0);
  EXPECT_EQ(ours->conflicts, 0);
  EXPECT_GE(*ours->min_pet_s, 1.0);
  EXPECT_GT(naive->collisions, 0);
}

TEST(Simulate, BadScenarioIsAnError) {
  sim::Scenario s;
  s.road.lanes = 0;
  EXPECT_EQ(sim::simulate_run(s, 1).status.code, StatusCode::invalid_argument);
  EXPECT_EQ(sim::simulate(sim::Scenario{}, 0, 1).status.code, StatusCode::invalid_argument);
}

}  // namespace
