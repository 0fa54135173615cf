#include "roadcross/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace roadcross::sim {

const char* to_string(Policy policy) noexcept {
  switch (policy) {
    case Policy::ours:
      return "ours";
    case Policy::hcm:
      return "hcm";
    case Policy::naive:
      return "naive";
  }
  return "unknown";
}

bool parse_policy(const std::string& text, Policy& policy) noexcept {
  for (Policy p : {Policy::ours, Policy::hcm, Policy::naive}) {
    if (text == to_string(p)) {
      policy = p;
      return true;
    }
  }
  return false;
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// xoshiro256** seeded by splitmix64: the same stream on every platform (std's distributions
/// are implementation-defined, so they are not used).
class Random {
 public:
  explicit Random(std::uint64_t seed) {
    for (auto& word : state_) word = splitmix(seed);
  }
  static std::uint64_t splitmix(std::uint64_t& x) {
    std::uint64_t z = (x += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  }
  std::uint64_t next() {
    const std::uint64_t result = rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = rotl(state_[3], 45);
    return result;
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double normal() {  // Box-Muller, one value per call
    const double u1 = 1.0 - uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
  }
  double exponential(double rate) { return -std::log(1.0 - uniform()) / rate; }

 private:
  static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t state_[4];
};

struct Vehicle {
  double a_m = 0.0;  ///< centre, along its own direction of travel; the crossing is at a = 0
  double speed_mps = 0.0, desired_mps = 0.0;
  int passage = -1;  ///< index into the passages once it has entered the conflict area
};

/// When a vehicle occupied the robot's path (x within the robot's radius), in its lane.
struct Passage {
  int lane = 0;
  double enter_s = 0.0, exit_s = kInf;
};

/// One stage of the crossing: the lanes it crosses and where the robot starts it.
struct Stage {
  int first_lane = 0, last_lane = 0;  // inclusive
  double start_y_m = 0.0;             // the robot's centre when waiting
  double end_y_m = 0.0;               // ... when the stage is done
  int gap_stage = 0;                  // GapCrossing::stage (0: no island)
  bool holds(int lane) const { return lane >= first_lane && lane <= last_lane; }
};

struct Lane {
  int direction = 1;  ///< +1: drives towards +x
  double centre_y_m = 0.0;
  double next_arrival_s = 0.0;
  std::vector<Vehicle> vehicles;  ///< leader first
};

/// Every value in the range the simulation is meant for: outside it a run would not end (a
/// robot crawling at 1e-9 m/s), allocate without bound (2e9 lanes) or mean nothing.
Status check(const Scenario& s) {
  struct Bound {
    const char* name;
    double value, min, max;
  };
  const Bound bounds[] = {
      {"lanes", static_cast<double>(s.road.lanes), 1, 16},
      {"road width (m)", s.road.width_m, 1, 100},
      {"maxspeed (km/h)", s.road.maxspeed_kmh, 1, 300},
      {"sight (m)", s.road.sight_m, 1, 5000},
      {"volume (vehicles/h per lane)", s.volume_veh_h_per_lane, 0, 3600},
      {"robot speed (m/s)", s.robot.speed_mps, 0.1, 10},
      {"robot start-up time (s)", s.robot.startup_s, 0, 60},
      {"max wait (s)", s.max_wait_s, 1, 3600},
      {"warm-up (s)", s.warmup_s, 0, 3600},
      {"step (s)", s.step_s, 0.001, 1},
      {"decision period (s)", s.decision_period_s, 0.001, 10},
      {"vehicle length (m)", s.vehicle_length_m, 1, 30},
      {"kerb offset (m)", s.kerb_offset_m, 0, 10},
      {"naive distance (m)", s.naive_distance_m, 0.1, 5000},
      {"conflict PET (s)", s.conflict_pet_s, 0, 60},
  };
  for (const Bound& b : bounds) {
    if (!(b.value >= b.min && b.value <= b.max)) {  // negated: NaN fails too
      char text[160];
      std::snprintf(text, sizeof text, "simulate: %s is %g, must be in [%g, %g]", b.name, b.value,
                    b.min, b.max);
      return {StatusCode::invalid_argument, text};
    }
  }
  return {};
}

class Run {
 public:
  Run(const Scenario& s, std::uint64_t seed) : s_(s), random_(seed) {
    const double lane_width_m = s.road.width_m / s.road.lanes;
    const int forward_lanes = (s.road.lanes + 1) / 2;
    for (int j = 0; j < s.road.lanes; ++j) {
      Lane lane;
      lane.direction = j < forward_lanes ? 1 : -1;
      lane.centre_y_m = s.kerb_offset_m + (j + 0.5) * lane_width_m;
      lane.next_arrival_s = arrival_gap_s();
      lanes_.push_back(lane);
    }
    spawn_m_ = s.road.sight_m + 100.0;  // beyond the robot's sight: vehicles drive into view
    crossing_.start = {0.0, 0.0};
    crossing_.centre = {0.0, s.kerb_offset_m + 0.5 * s.road.width_m};
    crossing_.heading_rad = 0.5 * 3.14159265358979323846;
    crossing_.road_width_m = s.road.width_m;
    crossing_.lanes = s.road.lanes;
    crossing_.maxspeed_kmh = s.road.maxspeed_kmh;
    crossing_.junction_distance_m = s.road.junction_distance_m;
    options_ = s.gap;
    options_.sensor_range_m = s.road.sight_m;
    const double far_y_m = s.kerb_offset_m + s.road.width_m + s.robot.radius_m;
    if (s.road.refuge_island && s.road.lanes >= 2) {
      // The same halves as gap_decision's: lanes / 2 near, the rest far.
      const int near_lanes = s.road.lanes / 2;
      const double island_y_m = s.kerb_offset_m + near_lanes * lane_width_m;
      stages_ = {{0, near_lanes - 1, 0.0, island_y_m, 1},
                 {near_lanes, s.road.lanes - 1, island_y_m, far_y_m, 2}};
      crossing_.refuge_island = true;
    } else {
      stages_ = {{0, s.road.lanes - 1, 0.0, far_y_m, 0}};
    }
  }

  Result<RunMetrics> run() {
    const long steps_per_decision = std::max(1L, std::lround(s_.decision_period_s / s_.step_s));
    const long arrival_step = std::lround((s_.warmup_s + 10.0 * random_.uniform()) / s_.step_s);
    const long wait_steps = std::lround(s_.max_wait_s / s_.step_s);
    crossing_s_ = 0.0;
    for (const Stage& stage : stages_) crossing_s_ += walk_s(stage);
    const long tail_steps =
        std::lround((walk_s(stages_.back()) + s_.conflict_pet_s + 2.0) / s_.step_s);
    // Per stage: when the robot is ready to decide there, and when it said GO (-1: not yet).
    std::vector<long> ready_step(stages_.size(), -1), go_step(stages_.size(), -1);
    std::size_t stage = 0;
    ready_step[0] = arrival_step;
    long end_step = arrival_step + wait_steps + tail_steps;
    RunMetrics m;
    for (long i = 0; i < end_step; ++i) {
      const double t = static_cast<double>(i) * s_.step_s;
      if (stage < stages_.size() && i >= ready_step[stage] && i < ready_step[stage] + wait_steps &&
          (i - ready_step[stage]) % steps_per_decision == 0) {
        ++m.decisions;
        Result<bool> go = decide(t, stages_[stage]);
        if (!go.ok()) return {go.status, {}};
        if (*go) {
          go_step[stage] = i;
          if (stage + 1 < stages_.size()) {
            // Walks to the island, then decides again from there.
            ready_step[stage + 1] = i + std::lround(walk_s(stages_[stage]) / s_.step_s);
            end_step = ready_step[stage + 1] + wait_steps + tail_steps;
          } else {
            end_step = i + tail_steps;
          }
          ++stage;
        }
      }
      advance(t);
    }
    m.crossed = stage == stages_.size();
    for (std::size_t k = 0; k < stages_.size() && ready_step[k] >= 0; ++k) {
      const long until = go_step[k] >= 0 ? go_step[k] : ready_step[k] + wait_steps;
      const double waited_s =
          static_cast<double>(until) * s_.step_s - static_cast<double>(ready_step[k]) * s_.step_s;
      m.waiting_s += waited_s;
      if (k > 0) m.island_wait_s += waited_s;
      count_acceptable_gaps(ready_step[k], until, steps_per_decision, stages_[k], go_step[k] >= 0,
                            m);
    }
    if (m.crossed) {
      m.crossing_s = crossing_s_;
      m.min_pet_s = min_pet_s(go_step);
      m.collision = m.min_pet_s && *m.min_pet_s < 0.0;
      m.conflict = m.min_pet_s && *m.min_pet_s < s_.conflict_pet_s;
    }
    return {Status{}, m};
  }

 private:
  double arrival_gap_s() {
    const double rate = s_.volume_veh_h_per_lane / 3600.0;
    return rate > 0 ? random_.exponential(rate) : kInf;
  }

  double desired_speed_mps() {
    const double limit_mps = s_.road.maxspeed_kmh / 3.6;
    const double v = limit_mps * (1.0 + s_.speed_sd_fraction * random_.normal());
    return std::clamp(v, s_.min_speed_fraction * limit_mps, s_.max_speed_fraction * limit_mps);
  }

  void spawn(Lane& lane, double t) {
    const double length = s_.vehicle_length_m;
    while (lane.next_arrival_s <= t) {
      Vehicle v;
      v.a_m = -spawn_m_;
      v.desired_mps = v.speed_mps = desired_speed_mps();
      if (!lane.vehicles.empty()) {
        const Vehicle& last = lane.vehicles.back();
        const double gap_m = (last.a_m - length / 2) - (v.a_m + length / 2);
        if (gap_m < 2.0 + s_.time_gap_s * last.speed_mps) return;  // queue: try next step
        if (gap_m < 100.0) v.speed_mps = std::min(v.speed_mps, last.speed_mps);
      }
      lane.vehicles.push_back(v);
      lane.next_arrival_s += arrival_gap_s();
    }
  }

  /// One step of every vehicle: speed fluctuation about its desired speed (Ornstein-Uhlenbeck,
  /// 5 s time constant), then car following, then the conflict-area bookkeeping.
  void advance(double t) {
    const double dt = s_.step_s, theta = 0.2, length = s_.vehicle_length_m;
    for (std::size_t j = 0; j < lanes_.size(); ++j) {
      Lane& lane = lanes_[j];
      spawn(lane, t);
      for (std::size_t k = 0; k < lane.vehicles.size(); ++k) {
        Vehicle& v = lane.vehicles[k];
        double speed = v.speed_mps + theta * (v.desired_mps - v.speed_mps) * dt +
                       s_.speed_fluctuation_mps * std::sqrt(2.0 * theta * dt) * random_.normal();
        const Vehicle* leader = k > 0 ? &lane.vehicles[k - 1] : nullptr;
        if (leader) {
          const double gap_m = (leader->a_m - length / 2) - (v.a_m + length / 2);
          const double wanted_m = 2.0 + s_.time_gap_s * speed;
          if (gap_m < wanted_m) speed = std::min(speed, leader->speed_mps + (gap_m - wanted_m) / 2);
        }
        v.speed_mps = std::max(0.0, speed);
        const double before = v.a_m;
        v.a_m += v.speed_mps * dt;
        if (leader) v.a_m = std::min(v.a_m, leader->a_m - length - 1.0);
        v.a_m = std::max(v.a_m, before);
        record_passage(v, static_cast<int>(j), before, t);
      }
      // Far downstream and out of sight: no longer part of the experiment.
      while (!lane.vehicles.empty() && lane.vehicles.front().a_m > spawn_m_) {
        lane.vehicles.erase(lane.vehicles.begin());
      }
    }
  }

  void record_passage(Vehicle& v, int lane, double before_m, double t) {
    const double half = s_.vehicle_length_m / 2, r = s_.robot.radius_m, dt = s_.step_s;
    const double moved = v.a_m - before_m;
    if (moved <= 0) return;
    // Front reaches -r: enters the robot's path; rear passes +r: leaves it.
    if (v.passage < 0 && before_m + half < -r && v.a_m + half >= -r) {
      v.passage = static_cast<int>(passages_.size());
      passages_.push_back({lane, t + dt * (-r - before_m - half) / moved, kInf});
    } else if (v.passage < 0 && before_m + half >= -r) {
      return;  // spawned past the path (cannot happen: spawn is far upstream)
    }
    if (v.passage >= 0 && passages_[v.passage].exit_s == kInf && before_m - half < r &&
        v.a_m - half >= r) {
      passages_[v.passage].exit_s = t + dt * (r - before_m + half) / moved;
    }
  }

  /// Start-up plus the walk of one stage, seconds.
  double walk_s(const Stage& stage) const {
    return s_.robot.startup_s + (stage.end_y_m - stage.start_y_m) / s_.robot.speed_mps;
  }

  Result<bool> decide(double t, const Stage& stage) {
    tracks_.clear();
    double nearest_m = kInf;
    for (const Lane& lane : lanes_) {
      for (const Vehicle& v : lane.vehicles) {
        const double x = lane.direction * v.a_m;
        if (std::fabs(x) > s_.road.sight_m) continue;  // hidden: beyond sight
        TrackedVehicle track;
        const double vx = lane.direction * v.speed_mps;
        track.x_m = x - vx * s_.track_latency_s + s_.position_noise_m * random_.normal();
        track.y_m = lane.centre_y_m + s_.position_noise_m * random_.normal();
        track.vx_mps = vx + s_.velocity_noise_mps * random_.normal();
        track.vy_mps = s_.velocity_noise_mps * random_.normal();
        track.length_m = s_.vehicle_length_m;
        track.time_s = t - s_.track_latency_s;
        tracks_.push_back(track);
        nearest_m = std::min(nearest_m, std::fabs(track.x_m));
      }
    }
    if (s_.policy == Policy::naive) return {Status{}, nearest_m > s_.naive_distance_m};
    crossing_.start = {0.0, stage.start_y_m};
    crossing_.stage = stage.gap_stage == 0 ? 1 : stage.gap_stage;
    const Result<GapDecision> d =
        s_.policy == Policy::ours
            ? gap_decision(crossing_, s_.robot, tracks_, t, options_)
            : hcm_gap_decision(crossing_, s_.robot, tracks_, t, options_, s_.hcm);
    if (!d.ok()) return {d.status, {}};
    return {Status{}, d->verdict == GapVerdict::go};
  }

  /// The robot's occupation of a lane's vehicle band when it starts the stage at go_s.
  std::pair<double, double> robot_band(int lane, const Stage& stage, double go_s) const {
    const double half = s_.vehicle_width_m / 2, r = s_.robot.radius_m, v = s_.robot.speed_mps;
    const double y = lanes_[lane].centre_y_m - stage.start_y_m;
    return {go_s + s_.robot.startup_s + std::max(0.0, y - half - r) / v,
            go_s + s_.robot.startup_s + (y + half + r) / v};
  }

  /// Smallest PET over the recorded passages in the stage's lanes if it starts at go_s
  /// (negative: a collision), unset when none.
  std::optional<double> stage_min_pet_s(const Stage& stage, double go_s) const {
    std::optional<double> best;
    for (const Passage& p : passages_) {
      if (!stage.holds(p.lane)) continue;
      const auto [in, out] = robot_band(p.lane, stage, go_s);
      const double pet = std::max(p.enter_s - out, in - p.exit_s);
      if (!best || pet < *best) best = pet;
    }
    return best;
  }

  /// Smallest PET over every stage, each started at its GO step.
  std::optional<double> min_pet_s(const std::vector<long>& go_steps) const {
    std::optional<double> best;
    for (std::size_t k = 0; k < stages_.size(); ++k) {
      const std::optional<double> pet =
          stage_min_pet_s(stages_[k], static_cast<double>(go_steps[k]) * s_.step_s);
      if (pet && (!best || *pet < *best)) best = pet;
    }
    return best;
  }

  /// Hindsight: a decision tick is an acceptable gap when starting the stage then would have
  /// kept every PET in its lanes (also of vehicles the robot could not see) at or above the
  /// conflict threshold. `went`: the stage ended with GO at to_step.
  void count_acceptable_gaps(long from_step, long to_step, long every, const Stage& stage,
                             bool went, RunMetrics& m) const {
    bool previous = false;
    const bool first_stage = stage.first_lane == 0;
    for (long i = from_step; i <= to_step; i += every) {
      const std::optional<double> pet = stage_min_pet_s(stage, static_cast<double>(i) * s_.step_s);
      const bool acceptable = !pet || *pet >= s_.conflict_pet_s;
      if (acceptable && !previous) ++m.acceptable_gaps_offered;
      previous = acceptable;
      if (i == to_step && went) {
        m.used_acceptable_gap = (first_stage || m.used_acceptable_gap) && acceptable;
      }
    }
  }

  const Scenario& s_;
  Random random_;
  std::vector<Lane> lanes_;
  std::vector<Passage> passages_;
  std::vector<TrackedVehicle> tracks_;
  GapCrossing crossing_;
  GapOptions options_;
  std::vector<Stage> stages_;
  double spawn_m_ = 0.0, crossing_s_ = 0.0;
};

}  // namespace

Result<RunMetrics> simulate_run(const Scenario& scenario, std::uint64_t seed) noexcept {
  if (Status s = check(scenario); !s.ok()) return {s, {}};
  try {
    return Run(scenario, seed).run();
  } catch (const std::exception& e) {  // only std::bad_alloc can get here
    return {Status{StatusCode::internal, std::string("simulate: ") + e.what()}, {}};
  }
}

std::uint64_t run_seed(std::uint64_t seed, int index) noexcept {
  std::uint64_t x = seed ^ (0xD1B54A32D192ED03ULL * static_cast<std::uint64_t>(index + 1));
  return Random::splitmix(x);
}

Result<Aggregate> simulate(const Scenario& scenario, int runs, std::uint64_t seed) noexcept {
  if (runs < 1 || runs > kMaxRuns) {
    return {Status{StatusCode::invalid_argument, "simulate: runs must be in [1, 100000]"}, {}};
  }
  Aggregate a;
  std::vector<double> waits;
  int used = 0, offered = 0;
  double crossing_sum = 0.0;
  try {
    waits.reserve(static_cast<std::size_t>(runs));
    for (int i = 0; i < runs; ++i) {
      const Result<RunMetrics> r = simulate_run(scenario, run_seed(seed, i));
      if (!r.ok()) return {r.status, {}};
      ++a.runs;
      a.crossed += r->crossed;
      a.collisions += r->collision;
      a.conflicts += r->conflict;
      waits.push_back(r->waiting_s);
      if (r->crossed) crossing_sum += r->crossing_s;
      used += r->used_acceptable_gap;
      offered += r->acceptable_gaps_offered;
      if (r->min_pet_s && (!a.min_pet_s || *r->min_pet_s < *a.min_pet_s))
        a.min_pet_s = r->min_pet_s;
    }
    double sum = 0.0;
    for (double w : waits) sum += w;
    a.mean_wait_s = sum / runs;
    std::sort(waits.begin(), waits.end());
    a.p95_wait_s = waits[static_cast<std::size_t>(std::ceil(0.95 * runs)) - 1];
    a.mean_crossing_s = a.crossed > 0 ? crossing_sum / a.crossed : 0.0;
    a.acceptable_gap_share = offered > 0 ? static_cast<double>(used) / offered : 0.0;
  } catch (const std::exception& e) {
    return {Status{StatusCode::internal, std::string("simulate: ") + e.what()}, {}};
  }
  return {Status{}, a};
}

}  // namespace roadcross::sim
