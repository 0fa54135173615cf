// A crossing simulator: traffic on a straight road near a crossing place, a robot that waits at
// the kerb and crosses when its policy says GO, and safety/efficiency metrics. Seeded and
// deterministic (own random number generator: the same seed gives the same numbers with every
// standard library). Depends on the runtime (for the gap policies) and the standard library only.
//
// Frame: the road runs along x (metres, the crossing line at x = 0); the robot waits at y = 0 on
// the near kerb and crosses towards +y. Right-hand traffic: the near half of the lanes drives
// towards +x, the far half towards -x (a single lane drives towards +x).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "roadcross/gap.hpp"
#include "roadcross/runtime.hpp"

namespace roadcross::sim {

struct Road {
  double width_m = 7.0;
  int lanes = 2;
  double maxspeed_kmh = 50.0;
  double sight_m = 200.0;  ///< the robot sees vehicles this far along the road each way
  /// Our policy allows for a vehicle turning in here (the simulated traffic has none).
  std::optional<double> junction_distance_m;
  /// A refuge island between the near lanes (lanes / 2) and the far ones: the robot crosses in
  /// two stages, deciding at the kerb for the near lanes, then on the island (its centre on
  /// the lane boundary) for the far lanes. Ignored on a one-lane road.
  bool refuge_island = false;
};

enum class Policy {
  ours,   ///< roadcross::gap_decision
  hcm,    ///< roadcross::hcm_gap_decision (HCM critical gap)
  naive,  ///< GO when the nearest visible vehicle is farther than naive_distance_m
};
const char* to_string(Policy policy) noexcept;
/// "ours", "hcm", "naive" -> policy; false for anything else.
bool parse_policy(const std::string& text, Policy& policy) noexcept;

struct Scenario {
  Road road;
  Policy policy = Policy::ours;
  double volume_veh_h_per_lane = 300.0;  ///< Poisson arrivals, vehicles per hour in each lane
  RobotMotion robot;
  GapOptions gap;  ///< ours and hcm; sensor_range_m is replaced by road.sight_m
  HcmOptions hcm;
  double naive_distance_m = 50.0;
  double kerb_offset_m = 0.5;  ///< the robot waits this far before the near edge

  // Traffic.
  double speed_sd_fraction = 0.1;  ///< desired speed ~ N(maxspeed, this x maxspeed) ...
  double min_speed_fraction = 0.7, max_speed_fraction = 1.15;  ///< ... clipped to these
  double speed_fluctuation_mps = 0.3;  ///< stationary s.d. of each driver's speed about its own
  double vehicle_length_m = 4.5, vehicle_width_m = 1.8;
  double time_gap_s = 1.0;  ///< car following: keep this time gap plus 2 m to the leader

  // Sensing.
  double position_noise_m = 0.2;    ///< s.d. of tracked positions
  double velocity_noise_mps = 0.2;  ///< s.d. of tracked velocities
  double track_latency_s = 0.1;     ///< tracks describe the world this long ago

  // Run.
  double step_s = 0.05;
  double decision_period_s = 0.1;
  double warmup_s = 40.0;       ///< traffic runs this long before the robot arrives (+ 0..10 s)
  double max_wait_s = 120.0;    ///< the robot gives up after waiting this long
  double conflict_pet_s = 1.0;  ///< a crossing with a PET below this is a conflict
};

struct RunMetrics {
  bool crossed = false;    ///< false: gave up after max_wait_s
  bool collision = false;  ///< robot and vehicle in the same conflict area at the same time
  bool conflict = false;   ///< collision, or PET below conflict_pet_s
  std::optional<double> min_pet_s;  ///< over the vehicles that passed the robot's lanes
  /// Arrival to GO (max_wait_s when it gave up); with a refuge island, the wait at the kerb
  /// plus the wait on the island.
  double waiting_s = 0.0;
  double island_wait_s = 0.0;        ///< of waiting_s, on the island (0 without one)
  double crossing_s = 0.0;           ///< moving: GO to the far side (both stages' walks)
  int acceptable_gaps_offered = 0;   ///< gaps (by hindsight) that began before GO (each stage's)
  bool used_acceptable_gap = false;  ///< GO (every stage's) fell in an acceptable gap
  int decisions = 0;
};

struct Aggregate {
  int runs = 0, crossed = 0, collisions = 0, conflicts = 0;
  double mean_wait_s = 0.0, p95_wait_s = 0.0, mean_crossing_s = 0.0;
  double acceptable_gap_share = 0.0;  ///< used / offered acceptable gaps, 0..1
  std::optional<double> min_pet_s;
};

/// One run; `seed` fixes everything random in it.
Result<RunMetrics> simulate_run(const Scenario& scenario, std::uint64_t seed) noexcept;

/// The seed of run `index` (0-based) of simulate(scenario, runs, seed).
std::uint64_t run_seed(std::uint64_t seed, int index) noexcept;

/// The most runs one simulate() call makes (each run simulates minutes of traffic).
inline constexpr int kMaxRuns = 100000;

/// `runs` runs (1..kMaxRuns) with seeds run_seed(seed, 0 .. runs - 1), aggregated.
/// invalid_argument when a scenario value is outside the range the simulation is meant for
/// (lanes 1..16, width 1..100 m, maxspeed 1..300 km/h, sight 1..5000 m, volume 0..3600
/// vehicles/h per lane, robot speed 0.1..10 m/s, waits up to an hour; the message names it).
Result<Aggregate> simulate(const Scenario& scenario, int runs, std::uint64_t seed) noexcept;

}  // namespace roadcross::sim
