#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"

namespace roadcross::cli {

NearestCommand::NearestCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("nearest", "the road centreline nearest to a position");
  query_.add_to(*app_);
  app_->add_option("--max-distance", max_distance_m_, "search radius, metres")
      ->capture_default_str();
}

int NearestCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<NearestRoad> road = map->nearest(query_.position(), max_distance_m_);
  if (!road.ok()) return query_.report_error(*map, road.status);
  if (query_.json) {
    std::cout << road_json(*road, map->info().zone).dump(2) << "\n";
    return 0;
  }
  std::printf("road      %s\n", road_label(*road).c_str());
  std::printf("distance  %.2f m\n", road->distance_m);
  std::printf("closest   E %.2f N %.2f (UTM zone %d%s)\n", road->closest.easting_m,
              road->closest.northing_m, map->info().zone.zone,
              map->info().zone.northern ? "N" : "S");
  return 0;
}

}  // namespace roadcross::cli
