#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"

namespace roadcross::cli {

HeadingCommand::HeadingCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("heading", "the road's direction and the heading that crosses it");
  query_.add_to(*app_);
  app_->add_option("--max-distance", max_distance_m_, "search radius, metres")
      ->capture_default_str();
}

int HeadingCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<RoadHeading> heading = map->road_heading(query_.position(), max_distance_m_);
  if (!heading.ok()) return query_.report_error(*map, heading.status);
  if (query_.json) {
    const nlohmann::ordered_json out = heading_json(*heading, map->info().zone);
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("road      %s, %.2f m away\n", road_label(heading->road).c_str(),
              heading->road.distance_m);
  std::printf("road      yaw %+.4f rad ENU (bearing %5.1f deg)\n", heading->road_heading_rad,
              heading->road_bearing_deg);
  std::printf(
      "cross     yaw %+.4f rad ENU (bearing %5.1f deg)%s\n", heading->crossing_heading_rad,
      heading->crossing_bearing_deg,
      heading->on_centreline ? ", on the centreline: side unknown" : ", from this side across");
  std::printf("frame     UTM grid; add %+.5f rad for a yaw from true east\n",
              heading->convergence_rad);
  return 0;
}

}  // namespace roadcross::cli
