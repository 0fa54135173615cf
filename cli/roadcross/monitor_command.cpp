#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/monitor.hpp"

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
  if (query_.uses_set()) {
    std::cerr << "roadcross monitor: takes one map file (--db once); sets of maps are for "
                 "nearest, heading, assess, better and batch\n";
    return 2;
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<CrossingPlan> plan = plan_crossing(*map, query_.position());
  if (!plan.ok()) return query_.report_error(*map, plan.status);
  const Result<CrossingProgress> p = monitor(*plan, Pose{{at_utm_[0], at_utm_[1]}, yaw_rad_});
  if (!p.ok()) return report_error(p.status);
  if (query_.json) {
    nlohmann::ordered_json out;
    out["state"] = to_string(p->state);
    out["progress"] = p->progress;
    out["lateral_deviation_m"] = p->lateral_deviation_m;
    out["heading_error_rad"] = p->heading_error_rad;
    out["plan_start_utm_m"] = {plan->start.easting_m, plan->start.northing_m};
    out["plan_start_lat_lon_deg"] = lat_lon_json(map->info().zone, plan->start);
    out["plan_target_utm_m"] = {plan->target.easting_m, plan->target.northing_m};
    out["plan_target_lat_lon_deg"] = lat_lon_json(map->info().zone, plan->target);
    out["plan_heading_rad"] = plan->heading_rad;
    std::cout << json_text(out, 2) << "\n";
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
