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

namespace {

/// The answer as text or JSON. `zone`: the answering map's UTM zone; `source` names the map of
/// a set that gave it (null for one map).
int print_heading(const RoadHeading& heading, const geo::UtmZone& zone, const MapSource* source,
                  bool json) {
  if (json) {
    std::cout << json_text(with_map_source(heading_json(heading, zone), source), 2) << "\n";
    return 0;
  }
  if (source) print_map_source(*source);
  std::printf("road      %s, %.2f m away\n", road_label(heading.road).c_str(),
              heading.road.distance_m);
  std::printf("road      yaw %+.4f rad ENU (bearing %5.1f deg)\n", heading.road_heading_rad,
              heading.road_bearing_deg);
  std::printf(
      "cross     yaw %+.4f rad ENU (bearing %5.1f deg)%s\n", heading.crossing_heading_rad,
      heading.crossing_bearing_deg,
      heading.on_centreline ? ", on the centreline: side unknown" : ", from this side across");
  std::printf("frame     UTM grid; add %+.5f rad for a yaw from true east\n",
              heading.convergence_rad);
  if (heading.heading_spread_rad) {
    std::printf("spread    %.4f rad (%.1f deg) over the position's region\n",
                *heading.heading_spread_rad, geo::rad_to_deg(*heading.heading_spread_rad));
  }
  return 0;
}

}  // namespace

int HeadingCommand::run() {
  if (query_.uses_set()) {
    std::optional<MapSet> set = open_set_or_report(query_.db_paths);
    if (!set) return 1;
    const auto heading = set->road_heading(query_.position(), max_distance_m_);
    if (!heading.ok()) return report_error(heading.status);
    return print_heading(heading->answer, set->map(heading->map.index).info().zone, &heading->map,
                         query_.json);
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<RoadHeading> heading = map->road_heading(query_.position(), max_distance_m_);
  if (!heading.ok()) return query_.report_error(*map, heading.status);
  return print_heading(*heading, map->info().zone, nullptr, query_.json);
}

}  // namespace roadcross::cli
