#include "roadcross/monitor.hpp"

#include <cmath>

namespace roadcross {

const char* to_string(CrossingState state) noexcept {
  switch (state) {
    case CrossingState::on_track:
      return "ON_TRACK";
    case CrossingState::drifting:
      return "DRIFTING";
    case CrossingState::leaving_corridor:
      return "LEAVING_CORRIDOR";
    case CrossingState::done:
      return "DONE";
  }
  return "UNKNOWN";
}

namespace {
bool finite(const PlanePoint& p) {
  return std::isfinite(p.easting_m) && std::isfinite(p.northing_m);
}
}  // namespace

Result<CrossingProgress> monitor(const CrossingPlan& plan, const Pose& pose,
                                 const MonitorOptions& options) noexcept {
  const auto invalid = [](const char* why) {
    return Result<CrossingProgress>{Status{StatusCode::invalid_argument, why}, std::nullopt};
  };
  if (!finite(plan.start) || !finite(plan.target) || !finite(pose.position) ||
      !std::isfinite(pose.yaw_rad)) {
    return invalid("monitor: NaN or infinite coordinate or yaw");
  }
  if (!(options.drift_m > 0 && options.corridor_half_width_m > 0 &&
        options.heading_tolerance_rad > 0 && options.done_margin_m >= 0)) {
    return invalid("monitor: thresholds must be positive");
  }
  const double dx = plan.target.easting_m - plan.start.easting_m;
  const double dy = plan.target.northing_m - plan.start.northing_m;
  const double length = std::hypot(dx, dy);
  if (!(length > 1e-6)) return invalid("monitor: the plan's start and target coincide");
  const double ux = dx / length, uy = dy / length;
  const double px = pose.position.easting_m - plan.start.easting_m;
  const double py = pose.position.northing_m - plan.start.northing_m;
  const double along = px * ux + py * uy;
  CrossingProgress out;
  out.progress = std::fmin(std::fmax(along / length, 0.0), 1.0);
  out.lateral_deviation_m = ux * py - uy * px;  // cross product: left of the line is positive
  out.heading_error_rad = geo::angle_difference_rad(pose.yaw_rad, std::atan2(dy, dx));
  const double lateral = std::fabs(out.lateral_deviation_m);
  if (lateral > options.corridor_half_width_m) {
    out.state = CrossingState::leaving_corridor;
  } else if (along >= length - options.done_margin_m) {
    out.state = CrossingState::done;
  } else if (lateral > options.drift_m ||
             std::fabs(out.heading_error_rad) > options.heading_tolerance_rad) {
    out.state = CrossingState::drifting;
  }
  return Result<CrossingProgress>{Status{}, out};
}

Result<CrossingPlan> plan_crossing(Map& map, const Position& position, double default_width_m,
                                   double kerb_margin_m) noexcept {
  const Result<RoadHeading> heading = map.road_heading(position);
  if (!heading.ok()) return Result<CrossingPlan>{heading.status, std::nullopt};
  const Result<Assessment> terms = map.assess(position);
  CrossingPlan plan;
  plan.road_width_m = (terms.ok() && terms->width_m) ? *terms->width_m : default_width_m;
  plan.start = heading->road.query;
  plan.heading_rad = heading->crossing_heading_rad;
  const double beyond = 0.5 * plan.road_width_m + kerb_margin_m;
  plan.target = {heading->road.closest.easting_m + beyond * std::cos(plan.heading_rad),
                 heading->road.closest.northing_m + beyond * std::sin(plan.heading_rad)};
  return Result<CrossingPlan>{Status{}, plan};
}

}  // namespace roadcross
