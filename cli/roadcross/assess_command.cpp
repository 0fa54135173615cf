#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/monitor.hpp"

namespace roadcross::cli {
namespace {

std::string number_or_dash(const std::optional<double>& value, const char* format) {
  if (!value) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, *value);
  return text;
}

std::string int_or_dash(const std::optional<int>& value) {
  return value ? std::to_string(*value) : std::string("-");
}

}  // namespace

AssessCommand::AssessCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("assess", "is this a suitable place to cross, and why not");
  query_.add_to(*app_);
  app_->add_option("--valid-distance", options_.valid_distance_m,
                   "valid within this distance of a centreline, metres (default: the DB's)");
  app_->add_option("--threshold", options_.threshold,
                   "suitable when score + context >= this (default: the DB's)");
}

int AssessCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<Assessment> result = map->assess(query_.position(), options_);
  if (!result.ok()) {
    std::cerr << "roadcross: " << result.status.message << "\n";
    return 1;
  }
  const Assessment& a = *result;
  if (query_.json) {
    std::cout << assessment_json(a).dump(2) << "\n";
    return 0;
  }
  const std::string name = a.road.name.empty() ? "(unnamed)" : a.road.name;
  std::printf("%s\n", a.suitable ? "SUITABLE place to cross"
                                 : (a.valid ? "NOT suitable here" : "NOT at a road"));
  std::printf("road        %s (%s, OSM way %lld), %.2f m away\n", name.c_str(),
              a.road.highway.c_str(), static_cast<long long>(a.road.osm_way_id), a.road.distance_m);
  std::printf("score       %s + context %s = %d (threshold %g)\n", int_or_dash(a.score).c_str(),
              int_or_dash(a.context_score).c_str(),
              a.score.value_or(0) + a.context_score.value_or(0), a.threshold);
  std::printf("rank        %s of 14   class %s   curvature %s (level %s, radius %s m)\n",
              int_or_dash(a.rank).c_str(), int_or_dash(a.class_cost).c_str(),
              int_or_dash(a.curvature_cost).c_str(), int_or_dash(a.curvature_level).c_str(),
              number_or_dash(a.radius_m, "%.0f").c_str());
  std::printf("junction    %s m along the road   designated crossing %s m\n",
              number_or_dash(a.junction_distance_m, "%.1f").c_str(),
              number_or_dash(a.crossing_distance_m, "%.1f").c_str());
  std::printf("terrain     %s, elevation cost %s of 9\n",
              a.landform ? ("landform " + *a.landform).c_str() : "no elevation data",
              int_or_dash(a.elevation_cost).c_str());
  std::printf("traffic     maxspeed %s km/h, %s lanes, %s m wide\n",
              number_or_dash(a.maxspeed_kmh, "%.0f").c_str(), int_or_dash(a.lanes).c_str(),
              number_or_dash(a.width_m, "%.1f").c_str());
  std::printf("sight       %s m forward, %s m backward, needs %s m\n",
              number_or_dash(a.sight_forward_m, "%.0f").c_str(),
              number_or_dash(a.sight_backward_m, "%.0f").c_str(),
              number_or_dash(a.required_sight_m, "%.0f").c_str());
  for (const std::string& code : a.reasons) {
    std::printf("  %-20s %s\n", code.c_str(), describe_reason(code));
  }
  if (!a.override_note.empty()) std::printf("  operator note: %s\n", a.override_note.c_str());
  return 0;
}

}  // namespace roadcross::cli

namespace roadcross::cli {

BetterCommand::BetterCommand(CLI::App& parent) {
  app_ =
      parent.add_subcommand("better", "better places to cross nearby, by walking along the road");
  query_.add_to(*app_);
  app_->add_option("--radius", options_.search_radius_m, "walking distance to search, metres")
      ->capture_default_str();
  app_->add_option("--max", options_.max_candidates, "at most this many places")
      ->capture_default_str();
  app_->add_option("--threshold", options_.assess.threshold,
                   "suitable when score + context >= this (default: the DB's)");
}

int BetterCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<BetterPlaces> result = map->better_place(query_.position(), options_);
  if (!result.ok()) {
    std::cerr << "roadcross: " << result.status.message << "\n";
    return 1;
  }
  if (query_.json) {
    const nlohmann::ordered_json out = better_places_json(*result);
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (result->candidates.empty()) {
    std::printf("%s\n", result->reason.c_str());
    return 0;
  }
  std::printf("%-4s %9s %8s %-9s %-19s %s\n", "#", "walk (m)", "score", "crossing",
              "go to (UTM E, N)", "cross yaw (rad)");
  int rank = 1;
  for (const Candidate& c : result->candidates) {
    std::printf("%-4d %9.1f %8d %-9s %9.1f %9.1f %+8.3f\n", rank++, c.walking_distance_m, c.score,
                c.designated_crossing ? "zebra" : "-", c.point.easting_m, c.point.northing_m,
                c.crossing_heading_rad);
  }
  return 0;
}

}  // namespace roadcross::cli

namespace roadcross::cli {

MonitorCommand::MonitorCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("monitor",
                               "progress of a crossing planned from the start position, at a pose");
  query_.add_to(*app_);
  app_->add_option("--at", at_utm_, "the robot's current UTM easting and northing, metres")
      ->expected(2)
      ->required();
  app_->add_option("--yaw", yaw_rad_, "the robot's current ENU yaw (UTM grid), radians")
      ->required();
}

int MonitorCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<CrossingPlan> plan = plan_crossing(*map, query_.position());
  if (!plan.ok()) {
    std::cerr << "roadcross: " << plan.status.message << "\n";
    return 1;
  }
  const Result<CrossingProgress> p = monitor(*plan, Pose{{at_utm_[0], at_utm_[1]}, yaw_rad_});
  if (!p.ok()) {
    std::cerr << "roadcross: " << p.status.message << "\n";
    return 1;
  }
  if (query_.json) {
    nlohmann::ordered_json out;
    out["state"] = to_string(p->state);
    out["progress"] = p->progress;
    out["lateral_deviation_m"] = p->lateral_deviation_m;
    out["heading_error_rad"] = p->heading_error_rad;
    out["plan_start_utm_m"] = {plan->start.easting_m, plan->start.northing_m};
    out["plan_target_utm_m"] = {plan->target.easting_m, plan->target.northing_m};
    out["plan_heading_rad"] = plan->heading_rad;
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%s  progress %.0f %%  lateral %+.2f m  heading error %+.3f rad\n",
              to_string(p->state), 100.0 * p->progress, p->lateral_deviation_m,
              p->heading_error_rad);
  std::printf("plan      E %.1f N %.1f -> E %.1f N %.1f, yaw %+.3f rad\n", plan->start.easting_m,
              plan->start.northing_m, plan->target.easting_m, plan->target.northing_m,
              plan->heading_rad);
  return 0;
}

}  // namespace roadcross::cli
