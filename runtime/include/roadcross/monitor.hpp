// Watching the crossing itself: how far along the robot is, how far it has drifted from the
// line across the road, and whether it is still in the corridor. Pure computation on a plan and
// a pose: no DB access, no allocation, noexcept — cheap enough for a 100 Hz control loop.
#pragma once

#include "roadcross/runtime.hpp"

namespace roadcross {

/// A crossing: from the start point, straight across to the far-side target (UTM metres).
struct CrossingPlan {
  PlanePoint start;
  PlanePoint target;
  double heading_rad = 0.0;   ///< ENU yaw (UTM grid) from start to target
  double road_width_m = 0.0;  ///< the carriageway width the plan assumed
};

struct Pose {
  PlanePoint position;   ///< UTM metres, the map's zone
  double yaw_rad = 0.0;  ///< ENU yaw in the UTM grid frame, any value (normalised inside)
};

struct MonitorOptions {
  double drift_m = 0.5;                 ///< DRIFTING beyond this lateral deviation, metres
  double corridor_half_width_m = 1.5;   ///< LEAVING_CORRIDOR beyond this, metres
  double heading_tolerance_rad = 0.35;  ///< DRIFTING beyond this heading error (~20 degrees)
  double done_margin_m = 0.2;           ///< DONE within this of the target along the line
};

enum class CrossingState { on_track, drifting, leaving_corridor, done };

const char* to_string(CrossingState state) noexcept;

struct CrossingProgress {
  double progress = 0.0;             ///< 0 at the start .. 1 at the target, clamped
  double lateral_deviation_m = 0.0;  ///< signed: > 0 left of the line start -> target
  double heading_error_rad = 0.0;    ///< pose yaw minus plan heading, (-pi, pi]
  CrossingState state = CrossingState::on_track;
};

/// Progress of `pose` on `plan`. invalid_argument for NaN or infinite input, a plan whose
/// start and target coincide, or options that are not positive.
Result<CrossingProgress> monitor(const CrossingPlan& plan, const Pose& pose,
                                 const MonitorOptions& options = {}) noexcept;

/// A plan from a position beside the road: start there, head across (Map::road_heading), and
/// aim at the point on the far side, half the road width (the DB's width_m, else
/// `default_width_m`) plus `kerb_margin_m` beyond the centreline.
Result<CrossingPlan> plan_crossing(Map& map, const Position& position, double default_width_m = 6.0,
                                   double kerb_margin_m = 0.5) noexcept;

}  // namespace roadcross
