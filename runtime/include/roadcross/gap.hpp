// Traffic gap acceptance: may the robot start crossing now, given the tracked vehicles?
//
// Model (docs/runtime.md, "Gap acceptance"): the road is straight near the crossing; its
// carriageway is split into equal lanes. Each vehicle keeps its lateral place (hence its lane)
// and moves along the road at its current speed, within a speed uncertainty. It occupies the
// crossing corridor (the robot's path widened by a safety buffer) during an interval; the robot
// occupies that vehicle's lane during another. The smallest gap between the two intervals over
// all vehicles is the post-encroachment time (PET) margin. Vehicles not seen because the road
// is seen only up to the sensor range are an "unseen vehicle" at that range, at the speed limit
// and above. Pure computation: no DB access, noexcept.
#pragma once

#include <cstddef>
#include <optional>
#if __cplusplus >= 202002L
#include <span>
#endif

#include "roadcross/monitor.hpp"
#include "roadcross/runtime.hpp"

namespace roadcross {

/// The crossing as the gap decision sees it (all in the map's UTM grid, metres).
struct GapCrossing {
  PlanePoint start;              ///< where the robot waits; it crosses from here along heading_rad
  PlanePoint centre;             ///< the road centreline on the crossing line
  double heading_rad = 0.0;      ///< ENU yaw (UTM grid) across the road
  double road_width_m = 6.0;     ///< carriageway width, centred on `centre`
  int lanes = 2;                 ///< equal lanes across the carriageway, >= 1
  double maxspeed_kmh = 50.0;    ///< the speed limit, for the vehicle the sensors cannot see
  double convergence_rad = 0.0;  ///< true_yaw = grid_yaw + convergence (vehicles in robot ENU)
  /// Distance along the road to the nearest junction, where a vehicle can turn in unseen.
  std::optional<double> junction_distance_m;
  /// Road visible from the kerb each way along the road (the DB's sight_forward_m /
  /// sight_backward_m: bends, buildings, walls and terrain), metres, >= 0. A vehicle can hide
  /// beyond it even inside the sensor range. Unset: only the sensor range limits the view.
  std::optional<double> sight_forward_m, sight_backward_m;
  /// A refuge island in the middle of the carriageway (the DB's crossing_island): the crossing
  /// is two stages, each over half the lanes (lanes / 2 near, the rest far), with a wait on
  /// the island between. Ignored on a one-lane road.
  bool refuge_island = false;
  /// With an island: 1 = from the kerb to the island over the near lanes (`start` at the
  /// kerb), 2 = from the island over the far lanes (`start` on the island). Must be 1 or 2.
  int stage = 1;
  /// Under position uncertainty: how far the robot may be from its fix along the road (half
  /// the extent of the position's region along it), metres, >= 0; 0 for an exact position.
  /// Vehicles tracked in the UTM grid may be that much nearer than they seem: the gap decision
  /// widens the robot's corridor by it for them (not for those tracked relative to the robot),
  /// and junction_distance_m is already shortened by it.
  double along_road_uncertainty_m = 0.0;
};

/// Defaults for what the DB does not say.
struct GapCrossingDefaults {
  double width_m = 6.0;        ///< carriageway width when the DB has no width_m
  double lane_width_m = 3.25;  ///< lanes = round(width / this) when the DB has no lanes
  double maxspeed_kmh = 50.0;  ///< when the DB has no maxspeed
};

/// The crossing at `position`: plan_crossing's start and heading, the DB's lanes, width,
/// maxspeed (else `defaults`), junction distance, sight distances and refuge island, and with the
/// position's uncertainty, along_road_uncertainty_m from its region. With an island, a position
/// within a quarter of the carriageway's width of the centreline is on the island (stage 2); any
/// other is at the kerb (stage 1).
Result<GapCrossing> gap_crossing(Map& map, const Position& position,
                                 const GapCrossingDefaults& defaults = {}) noexcept;

/// The robot's crossing behaviour.
struct RobotMotion {
  double speed_mps = 1.2;  ///< crossing speed once moving, > 0
  double startup_s = 1.0;  ///< from the decision to moving at speed_mps, >= 0
  double radius_m = 0.4;   ///< half the robot's footprint, along and across its path, >= 0
};

/// One tracked vehicle. Position and velocity are in the map's UTM grid, or in the robot's
/// local ENU frame (east, north, origin at the crossing start, true north).
struct TrackedVehicle {
  enum class Frame { utm, robot_enu };
  Frame frame = Frame::utm;
  double x_m = 0.0;  ///< easting (utm) or east offset from the crossing start (robot_enu)
  double y_m = 0.0;  ///< northing (utm) or north offset (robot_enu)
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double length_m = 4.5;                        ///< > 0
  std::optional<double> speed_uncertainty_mps;  ///< unset: GapOptions::speed_uncertainty_fraction
  double time_s = 0.0;  ///< when it was observed, same clock as `now_s`, <= now_s
};

struct GapOptions {
  double min_pet_s = 1.2;        ///< GO only if every predicted PET is at least this
  double safety_buffer_m = 0.5;  ///< added on each side of the robot's corridor along the road
  double speed_uncertainty_fraction = 0.1;  ///< speed known to +-this fraction, >= 0
  double stopped_speed_mps = 0.1;           ///< slower along the road = stopped (never arrives)
  double max_track_age_s = 0.5;             ///< older tracks are stale: WAIT until refreshed
  double sensor_range_m = 200.0;            ///< road seen this far each way from the crossing, > 0
  double unseen_speed_factor = 1.2;         ///< the unseen vehicle drives maxspeed x this
  double turning_speed_kmh = 25.0;  ///< a vehicle turning in at the junction (x unseen factor)
};

enum class GapVerdict { go, wait };
enum class GapReason {
  clear,               ///< GO: every vehicle leaves the margin
  vehicle_conflict,    ///< WAIT: a vehicle's predicted PET is below the margin
  blocked,             ///< WAIT: a stopped vehicle stands in the corridor
  insufficient_sight,  ///< WAIT: an unseen vehicle (beyond the sensor range, or turning in at
                       ///< the junction) could arrive too soon
  stale_track,         ///< WAIT: a track is older than max_track_age_s
  gap_too_short,       ///< WAIT (HCM policy): the next vehicle arrives within the critical gap
};
const char* to_string(GapVerdict verdict) noexcept;
const char* to_string(GapReason reason) noexcept;

struct GapDecision {
  GapVerdict verdict = GapVerdict::wait;
  GapReason reason = GapReason::clear;
  int limiting_vehicle = -1;  ///< index into the vehicles; -1: none, or the unseen vehicle
  /// Smallest predicted PET over the vehicles if the robot started now, seconds (negative: the
  /// robot and the vehicle would occupy the conflict area together). Unset: no vehicle counts.
  std::optional<double> margin_s;
  /// Earliest time (the `now_s` clock) at which GO would hold under the same predictions;
  /// unset when never (blocked, insufficient sight, stale track).
  std::optional<double> earliest_start_s;
  /// 0: a one-stage crossing; 1 or 2: the stage of a two-stage crossing (refuge island) this
  /// decision is for. The lanes, times and sight below are that stage's.
  int stage = 0;
  double crossing_time_s = 0.0;   ///< start-up plus walking until the stage's far lane is cleared
  double required_sight_m = 0.0;  ///< road the robot must see each way to rule out unseen cars
  /// Road the robot does see each way: the sensor range, cut by the crossing's sight distances
  /// (the shorter side counts: the unseen vehicle may come from either), metres.
  double visible_road_m = 0.0;
  double critical_gap_s = 0.0;  ///< HCM t_c (hcm_gap_decision only)
  int vehicles_counted = 0;     ///< vehicles that will still reach the crossing
  int stale_tracks = 0;
  int beyond_sensor_range = 0;  ///< tracks farther than sensor_range_m (still counted)
};

/// Our policy: GO when every vehicle's predicted PET is at least min_pet_s, no track is stale
/// and the road is seen far enough (visible_road_m >= required_sight_m, and no junction inside
/// it from which a turning vehicle could arrive too soon). invalid_argument for NaN/infinite input,
/// a non-positive speed or length, a negative start-up time, a timestamp after now_s, or bad
/// options.
#if __cplusplus >= 202002L
Result<GapDecision> gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                 std::span<const TrackedVehicle> vehicles, double now_s,
                                 const GapOptions& options = {}) noexcept;
#endif
/// The same for C++17 callers (ROS1 nodes): `vehicle_count` vehicles from `vehicles` (which may
/// be null when the count is 0).
Result<GapDecision> gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                 const TrackedVehicle* vehicles, std::size_t vehicle_count,
                                 double now_s, const GapOptions& options = {}) noexcept;

/// HCM 2010 pedestrian critical gap: t_c = L / S_p + t_s (crossing length = road width, or the
/// stage's lanes' width at a refuge island, the robot's speed, start-up and clearance time).
struct HcmOptions {
  double start_clearance_s = 3.0;  ///< t_s, the HCM's pedestrian start-up and clearance time
};
double hcm_critical_gap_s(double crossing_length_m, double speed_mps,
                          double start_clearance_s) noexcept;

/// The HCM reference policy: GO when no vehicle is in the crossing and the next one (any lane,
/// at its measured speed) reaches it no sooner than t_c from now. No sight-distance or stale-track
/// rule: that is the classic method. Same input checks as gap_decision.
#if __cplusplus >= 202002L
Result<GapDecision> hcm_gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                     std::span<const TrackedVehicle> vehicles, double now_s,
                                     const GapOptions& options = {},
                                     const HcmOptions& hcm = {}) noexcept;
#endif
/// The same for C++17 callers.
Result<GapDecision> hcm_gap_decision(const GapCrossing& crossing, const RobotMotion& robot,
                                     const TrackedVehicle* vehicles, std::size_t vehicle_count,
                                     double now_s, const GapOptions& options = {},
                                     const HcmOptions& hcm = {}) noexcept;

/// How far along the road the robot can see at a place: the sensor range, cut by the DB's
/// sight_min_m (schema v2: terrain, buildings, walls and bends, computed by roadcross-build).
/// Where the DB has no sight distance (schema v1 DBs, tunnels) the bend estimate stands in: the
/// chord visible past an obstruction `clearance_m` inside the curve, sqrt(8 R m), R = the
/// assessment's radius_m. Junctions do not block the view; gap_decision handles them.
double sight_distance_m(const Assessment& assessment, double sensor_range_m,
                        double clearance_m = 3.0) noexcept;

}  // namespace roadcross
