// Gap acceptance (roadcross/gap.hpp). Times are relative to `now` inside this file; the
// decision converts them back to the caller's clock.
#include "roadcross/gap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <vector>

namespace roadcross {

const char* to_string(GapVerdict verdict) noexcept {
  return verdict == GapVerdict::go ? "GO" : "WAIT";
}

const char* to_string(GapReason reason) noexcept {
  switch (reason) {
    case GapReason::clear:
      return "CLEAR";
    case GapReason::vehicle_conflict:
      return "VEHICLE_CONFLICT";
    case GapReason::blocked:
      return "BLOCKED";
    case GapReason::insufficient_sight:
      return "INSUFFICIENT_SIGHT";
    case GapReason::stale_track:
      return "STALE_TRACK";
    case GapReason::gap_too_short:
      return "GAP_TOO_SHORT";
  }
  return "UNKNOWN";
}

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Frame {
  double hx, hy;       // unit vector across the road (crossing heading)
  double ux, uy;       // unit vector along the road (right of the crossing heading)
  double near_edge_m;  // carriageway edges as distances from the start along the heading
  double lane_width_m;
  int lanes;
};

/// When the robot, starting at t0 = 0, occupies a band [lo, hi] across the road: enter and
/// exit offsets in seconds. Its footprint reaches radius_m ahead and behind its centre.
struct BandTimes {
  double enter_s, exit_s;
};

BandTimes band_times(const RobotMotion& robot, double lo_m, double hi_m) {
  const double enter_m = lo_m - robot.radius_m;
  // Already inside the band while standing still: occupied from the decision on.
  const double enter_s = enter_m <= 0.0 ? 0.0 : robot.startup_s + enter_m / robot.speed_mps;
  const double exit_s = robot.startup_s + std::max(0.0, hi_m + robot.radius_m) / robot.speed_mps;
  return {enter_s, exit_s};
}

BandTimes lane_times(const Frame& f, const RobotMotion& robot, int lane) {
  const double lo = f.near_edge_m + lane * f.lane_width_m;
  return band_times(robot, lo, lo + f.lane_width_m);
}

/// A vehicle's predicted occupation of the corridor, relative to now.
struct Occupation {
  bool counts = false;  // false: already past, or stopped outside the corridor
  bool stopped_inside = false;
  double enter_s = 0.0;  // earliest (fastest plausible speed), >= 0
  double exit_s = 0.0;   // latest (slowest plausible speed), may be infinite
  int lane = 0;
  double along_m = 0.0;  // distance along the road from the crossing line, signed
};

bool finite(double v) {
  return std::isfinite(v);
}

/// The lanes a decision covers: all of them, or one stage's half at a refuge island.
struct StageLanes {
  int first = 0, last = 0;  // inclusive lane indices, 0 = nearest the kerb the robot left
  int stage = 0;            // 0: one stage
  bool holds(int lane) const { return lane >= first && lane <= last; }
  int count() const { return last - first + 1; }
};

StageLanes stage_lanes(const GapCrossing& c) {
  if (!c.refuge_island || c.lanes < 2) return {0, c.lanes - 1, 0};
  const int near_lanes = c.lanes / 2;  // an odd lane count: the far half has the extra lane
  if (c.stage == 2) return {near_lanes, c.lanes - 1, 2};
  return {0, near_lanes - 1, 1};
}

Status invalid(const char* why) {
  return Status{StatusCode::invalid_argument, why};
}

Status check_common(const GapCrossing& c, const RobotMotion& r, double now_s, const GapOptions& o) {
  if (!finite(c.start.easting_m) || !finite(c.start.northing_m) || !finite(c.centre.easting_m) ||
      !finite(c.centre.northing_m) || !finite(c.heading_rad) || !finite(c.convergence_rad) ||
      !finite(now_s)) {
    return invalid("gap: NaN or infinite crossing coordinate, heading or time");
  }
  if (c.refuge_island && c.stage != 1 && c.stage != 2) {
    return invalid("gap: the stage of a crossing with a refuge island must be 1 or 2");
  }
  if (!(c.road_width_m > 0) || c.lanes < 1 || !(c.maxspeed_kmh > 0) || !finite(c.road_width_m) ||
      !finite(c.maxspeed_kmh) || (c.junction_distance_m && !(*c.junction_distance_m >= 0))) {
    return invalid("gap: road width, lanes and maxspeed must be positive");
  }
  if (!(c.along_road_uncertainty_m >= 0) || !finite(c.along_road_uncertainty_m)) {
    return invalid("gap: along_road_uncertainty_m must be finite and >= 0 metres");
  }
  for (const std::optional<double>& sight_m : {c.sight_forward_m, c.sight_backward_m}) {
    if (sight_m && !(*sight_m >= 0)) {  // also NaN; +infinity means "unlimited"
      return invalid("gap: a sight distance must be >= 0 metres");
    }
  }
  if (!(r.speed_mps > 0) || !finite(r.speed_mps)) {
    return invalid("gap: the robot's crossing speed must be positive (m/s)");
  }
  if (!(r.startup_s >= 0) || !finite(r.startup_s) || !(r.radius_m >= 0) || !finite(r.radius_m)) {
    return invalid("gap: the robot's start-up time and radius must be >= 0");
  }
  if (!(o.min_pet_s >= 0) || !(o.safety_buffer_m >= 0) || !(o.speed_uncertainty_fraction >= 0) ||
      !(o.stopped_speed_mps >= 0) || !(o.max_track_age_s > 0) || !(o.sensor_range_m > 0) ||
      !(o.unseen_speed_factor > 0) || !(o.turning_speed_kmh > 0)) {
    return invalid("gap: options must be >= 0 (age, sensor range, unseen and turning speed > 0)");
  }
  return {};
}

Status check_vehicle(const TrackedVehicle& v, double now_s) {
  if (!finite(v.x_m) || !finite(v.y_m) || !finite(v.vx_mps) || !finite(v.vy_mps) ||
      !finite(v.time_s) || !finite(v.length_m)) {
    return invalid("gap: a vehicle has a NaN or infinite position, velocity or timestamp");
  }
  if (!(v.length_m > 0)) return invalid("gap: a vehicle's length must be positive (metres)");
  if (v.speed_uncertainty_mps && !(*v.speed_uncertainty_mps >= 0)) {
    return invalid("gap: a vehicle's speed uncertainty must be >= 0 (m/s)");
  }
  if (v.time_s > now_s) {
    return invalid("gap: a vehicle's timestamp is in the future (after now): clocks differ?");
  }
  return {};
}

/// The road seen each way: the sensor range, cut by the shorter sight distance.
double visible_road_m(const GapCrossing& c, const GapOptions& o) {
  double visible_m = o.sensor_range_m;
  if (c.sight_forward_m) visible_m = std::min(visible_m, *c.sight_forward_m);
  if (c.sight_backward_m) visible_m = std::min(visible_m, *c.sight_backward_m);
  return visible_m;
}

Result<Frame> make_frame(const GapCrossing& c) {
  Frame f{};
  f.hx = std::cos(c.heading_rad);
  f.hy = std::sin(c.heading_rad);
  f.ux = f.hy;  // the heading turned clockwise by 90 degrees: one direction along the road
  f.uy = -f.hx;
  const double centre_m = (c.centre.easting_m - c.start.easting_m) * f.hx +
                          (c.centre.northing_m - c.start.northing_m) * f.hy;
  f.near_edge_m = centre_m - 0.5 * c.road_width_m;
  f.lanes = c.lanes;
  f.lane_width_m = c.road_width_m / c.lanes;
  if (!(f.near_edge_m + c.road_width_m > 0)) {
    return {invalid("gap: the road is behind the robot's start along the crossing heading"), {}};
  }
  return {Status{}, f};
}

/// A vehicle's position and velocity relative to the crossing (UTM grid).
void to_grid(const GapCrossing& c, const TrackedVehicle& v, double& e, double& n, double& ve,
             double& vn) {
  if (v.frame == TrackedVehicle::Frame::utm) {
    e = v.x_m, n = v.y_m, ve = v.vx_mps, vn = v.vy_mps;
    return;
  }
  // Robot ENU is true east/north; the grid is rotated by the convergence from it.
  const double cs = std::cos(-c.convergence_rad), sn = std::sin(-c.convergence_rad);
  e = c.start.easting_m + cs * v.x_m - sn * v.y_m;
  n = c.start.northing_m + sn * v.x_m + cs * v.y_m;
  ve = cs * v.vx_mps - sn * v.vy_mps;
  vn = sn * v.vx_mps + cs * v.vy_mps;
}

Occupation occupation(const GapCrossing& c, const Frame& f, const TrackedVehicle& v, double now_s,
                      double corridor_half_m, const GapOptions& o, bool with_uncertainty) {
  double e, n, ve, vn;
  to_grid(c, v, e, n, ve, vn);
  Occupation out;
  out.along_m = (e - c.centre.easting_m) * f.ux + (n - c.centre.northing_m) * f.uy;
  const double across_m = (e - c.start.easting_m) * f.hx + (n - c.start.northing_m) * f.hy;
  const double lane = std::floor((across_m - f.near_edge_m) / f.lane_width_m);
  out.lane = static_cast<int>(std::clamp(lane, 0.0, static_cast<double>(f.lanes - 1)));
  const double speed_along = ve * f.ux + vn * f.uy;
  const double speed = std::fabs(speed_along);
  // Centre-to-corridor overlap. A vehicle tracked in the grid is placed against the robot's fix,
  // which may be off along the road by the region's half extent; one tracked relative to the
  // robot is not.
  const double fix_error_m =
      v.frame == TrackedVehicle::Frame::utm ? c.along_road_uncertainty_m : 0.0;
  const double reach_m = corridor_half_m + fix_error_m + 0.5 * v.length_m;
  const double age_s = now_s - v.time_s;
  if (speed < o.stopped_speed_mps) {
    // Stopped (at a light, yielding, parked): never arrives under a constant-velocity
    // prediction; if it already stands in the corridor, the corridor stays taken.
    out.stopped_inside = std::fabs(out.along_m) <= reach_m;
    out.counts = out.stopped_inside;
    out.exit_s = kInf;
    return out;
  }
  const double ahead_m = speed_along > 0 ? out.along_m : -out.along_m;  // < 0: approaching
  const double u = with_uncertainty
                       ? v.speed_uncertainty_mps.value_or(o.speed_uncertainty_fraction * speed)
                       : 0.0;
  const double fast = speed + u, slow = speed - u;
  out.exit_s = (slow > 0 ? (reach_m - ahead_m) / slow : kInf) - age_s;
  if (out.exit_s <= 0) return out;  // already past the corridor
  out.enter_s = std::max(0.0, (-reach_m - ahead_m) / fast - age_s);
  out.counts = true;
  return out;
}

/// Earliest t >= 0 outside every open interval (lo, hi); infinite if none.
double earliest_free(std::vector<std::pair<double, double>>& forbidden) {
  std::sort(forbidden.begin(), forbidden.end());
  double t = 0.0;
  for (const auto& [lo, hi] : forbidden) {
    if (lo >= t) break;
    t = std::max(t, hi);
  }
  return t;
}

}  // namespace

Result<GapDecision> gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                 std::span<const TrackedVehicle> vehicles, double now_s,
                                 const GapOptions& options) noexcept {
  if (Status s = check_common(crossing, robot, now_s, options); !s.ok()) return {s, {}};
  for (const TrackedVehicle& v : vehicles) {
    if (Status s = check_vehicle(v, now_s); !s.ok()) return {s, {}};
  }
  const Result<Frame> frame = make_frame(crossing);
  if (!frame.ok()) return {frame.status, {}};
  const Frame& f = *frame;
  const double corridor_half_m = robot.radius_m + options.safety_buffer_m;
  const double m = options.min_pet_s;

  GapDecision d;
  const StageLanes lanes = stage_lanes(crossing);
  d.stage = lanes.stage;
  const BandTimes far = lane_times(f, robot, lanes.last);
  d.crossing_time_s = far.exit_s;
  // The vehicle nobody sees: just beyond the visible road (the sensor range, or nearer where a
  // bend, a building or a crest hides the road), in the far lane (the one the robot leaves
  // last), faster than the limit. The road must be seen far enough to rule it out.
  const double unseen_speed_mps = crossing.maxspeed_kmh / 3.6 * options.unseen_speed_factor;
  d.required_sight_m = unseen_speed_mps * (far.exit_s + m) + corridor_half_m;
  d.visible_road_m = visible_road_m(crossing, options);
  double unseen_margin_s = (d.visible_road_m - corridor_half_m) / unseen_speed_mps - far.exit_s;
  // A vehicle turning in at a junction inside the visible road appears there unannounced, at
  // turning speed (beyond it, the unseen vehicle above already covers it).
  if (crossing.junction_distance_m && *crossing.junction_distance_m < d.visible_road_m) {
    const double turning_mps = options.turning_speed_kmh / 3.6 * options.unseen_speed_factor;
    unseen_margin_s =
        std::min(unseen_margin_s,
                 (*crossing.junction_distance_m - corridor_half_m) / turning_mps - far.exit_s);
  }
  d.margin_s = unseen_margin_s;

  std::vector<std::pair<double, double>> forbidden;
  try {
    forbidden.reserve(vehicles.size());  // the only allocation; emplace_back below cannot throw
  } catch (const std::bad_alloc&) {
    return {Status{StatusCode::internal, "gap: out of memory"}, {}};
  }
  int margin_vehicle = -1, first_stale = -1, blocked_by = -1;
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    const TrackedVehicle& v = vehicles[i];
    const int index = static_cast<int>(i);
    if (now_s - v.time_s > options.max_track_age_s && d.stale_tracks++ == 0) first_stale = index;
    const Occupation o = occupation(crossing, f, v, now_s, corridor_half_m, options, true);
    if (std::fabs(o.along_m) > options.sensor_range_m) ++d.beyond_sensor_range;
    // At a refuge island, the other stage's lanes are not crossed now.
    if (!o.counts || !lanes.holds(o.lane)) continue;
    ++d.vehicles_counted;
    const BandTimes lane = lane_times(f, robot, o.lane);
    const double pet_s = std::max(o.enter_s - lane.exit_s, lane.enter_s - o.exit_s);
    if (pet_s < *d.margin_s) d.margin_s = pet_s, margin_vehicle = index;
    if (o.stopped_inside && blocked_by < 0) blocked_by = index;
    // Start times t at which this vehicle's PET would fall below m: the robot leaves its lane
    // later than (arrival - m), and enters it earlier than (departure + m).
    forbidden.emplace_back(o.enter_s - m - lane.exit_s, o.exit_s + m - lane.enter_s);
  }
  const double earliest_s = earliest_free(forbidden);
  d.limiting_vehicle = margin_vehicle;
  if (d.stale_tracks > 0) {
    // Where is it now? Unknown: wait until the tracker refreshes or drops it.
    d.reason = GapReason::stale_track;
    d.limiting_vehicle = first_stale;
  } else if (unseen_margin_s < m) {
    d.reason = GapReason::insufficient_sight;
    d.limiting_vehicle = -1;
  } else if (blocked_by >= 0) {
    d.reason = GapReason::blocked;
    d.limiting_vehicle = blocked_by;
  } else if (earliest_s > 0.0) {
    d.reason = GapReason::vehicle_conflict;
    if (std::isfinite(earliest_s)) d.earliest_start_s = now_s + earliest_s;
  } else {
    d.verdict = GapVerdict::go;
    d.earliest_start_s = now_s;
  }
  return {Status{}, d};
}

Result<GapDecision> gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                 const TrackedVehicle* vehicles, std::size_t vehicle_count,
                                 double now_s, const GapOptions& options) noexcept {
  return gap_decision(crossing, robot, std::span<const TrackedVehicle>(vehicles, vehicle_count),
                      now_s, options);
}

Result<GapDecision> hcm_gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                     const TrackedVehicle* vehicles, std::size_t vehicle_count,
                                     double now_s, const GapOptions& options,
                                     const HcmOptions& hcm) noexcept {
  return hcm_gap_decision(crossing, robot, std::span<const TrackedVehicle>(vehicles, vehicle_count),
                          now_s, options, hcm);
}

double hcm_critical_gap_s(double crossing_length_m, double speed_mps,
                          double start_clearance_s) noexcept {
  return crossing_length_m / speed_mps + start_clearance_s;
}

Result<GapDecision> hcm_gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                     std::span<const TrackedVehicle> vehicles, double now_s,
                                     const GapOptions& options, const HcmOptions& hcm) noexcept {
  if (Status s = check_common(crossing, robot, now_s, options); !s.ok()) return {s, {}};
  if (!(hcm.start_clearance_s >= 0) || !finite(hcm.start_clearance_s)) {
    return {invalid("gap: HCM start-up and clearance time must be >= 0"), {}};
  }
  for (const TrackedVehicle& v : vehicles) {
    if (Status s = check_vehicle(v, now_s); !s.ok()) return {s, {}};
  }
  const Result<Frame> frame = make_frame(crossing);
  if (!frame.ok()) return {frame.status, {}};
  const double corridor_half_m = robot.radius_m + options.safety_buffer_m;
  GapDecision d;
  const StageLanes lanes = stage_lanes(crossing);
  d.stage = lanes.stage;
  const double crossing_length_m = crossing.road_width_m * lanes.count() / crossing.lanes;
  d.critical_gap_s = hcm_critical_gap_s(crossing_length_m, robot.speed_mps, hcm.start_clearance_s);
  d.crossing_time_s = d.critical_gap_s;
  std::vector<std::pair<double, double>> forbidden;
  try {
    forbidden.reserve(vehicles.size());
  } catch (const std::bad_alloc&) {
    return {Status{StatusCode::internal, "gap: out of memory"}, {}};
  }
  double next_arrival_s = kInf;
  for (std::size_t i = 0; i < vehicles.size(); ++i) {
    const Occupation o =
        occupation(crossing, *frame, vehicles[i], now_s, corridor_half_m, options, false);
    if (std::fabs(o.along_m) > options.sensor_range_m) ++d.beyond_sensor_range;
    if (!o.counts || !lanes.holds(o.lane)) continue;
    ++d.vehicles_counted;
    if (o.enter_s < next_arrival_s)
      next_arrival_s = o.enter_s, d.limiting_vehicle = static_cast<int>(i);
    // The gap from a start at t to this vehicle's arrival must be at least t_c, and the
    // vehicle must have left the crossing.
    forbidden.emplace_back(o.enter_s - d.critical_gap_s, o.exit_s);
  }
  if (std::isfinite(next_arrival_s)) d.margin_s = next_arrival_s - d.critical_gap_s;
  const double earliest_s = earliest_free(forbidden);
  if (earliest_s > 0.0) {
    d.reason = GapReason::gap_too_short;
    if (std::isfinite(earliest_s)) d.earliest_start_s = now_s + earliest_s;
  } else {
    d.verdict = GapVerdict::go;
    d.earliest_start_s = now_s;
  }
  return {Status{}, d};
}

double sight_distance_m(const Assessment& assessment, double sensor_range_m,
                        double clearance_m) noexcept {
  double sight_m = sensor_range_m;
  if (assessment.sight_min_m) return std::min(sight_m, *assessment.sight_min_m);
  if (assessment.radius_m && *assessment.radius_m > 0 && clearance_m > 0) {
    sight_m = std::min(sight_m, std::sqrt(8.0 * *assessment.radius_m * clearance_m));
  }
  return sight_m;
}

Result<GapCrossing> gap_crossing(Map& map, const Position& position,
                                 const GapCrossingDefaults& defaults) noexcept {
  const Result<RoadHeading> heading = map.road_heading(position);
  if (!heading.ok()) return {heading.status, {}};
  const Result<Assessment> a = map.assess(position);
  if (!a.ok()) return {a.status, {}};
  GapCrossing c;
  c.start = heading->road.query;
  c.centre = heading->road.closest;
  c.heading_rad = heading->crossing_heading_rad;
  c.convergence_rad = heading->convergence_rad;
  c.road_width_m = a->width_m.value_or(defaults.width_m);
  c.lanes = a->lanes.value_or(
      std::max(1, static_cast<int>(std::lround(c.road_width_m / defaults.lane_width_m))));
  c.maxspeed_kmh = a->maxspeed_kmh.value_or(defaults.maxspeed_kmh);
  c.junction_distance_m = a->junction_distance_m;
  if (a->region) {
    // Half the region's extent along the road: for an ellipse with semi-axes a, b at angle t
    // from the road, sqrt((a cos t)^2 + (b sin t)^2).
    const double t = a->region->major_axis_yaw_rad - heading->road_heading_rad;
    c.along_road_uncertainty_m =
        std::hypot(a->region->semi_major_m * std::cos(t), a->region->semi_minor_m * std::sin(t));
    // The junction may be that much nearer than the fix says.
    if (c.junction_distance_m) {
      c.junction_distance_m = std::max(0.0, *c.junction_distance_m - c.along_road_uncertainty_m);
    }
  }
  c.sight_forward_m = a->sight_forward_m;
  c.sight_backward_m = a->sight_backward_m;
  c.refuge_island = a->crossing_island.value_or(false);
  // On the island: well inside the carriageway, near the centreline.
  c.stage = c.refuge_island && a->road.distance_m < 0.25 * c.road_width_m ? 2 : 1;
  return {Status{}, c};
}

}  // namespace roadcross
