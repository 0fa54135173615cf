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

namespace {

/// The answer as text or JSON; `source` names the map of a set that gave it (null for one map).
int print_nearest(const NearestRoad& road, const geo::UtmZone& zone, const MapSource* source,
                  bool json) {
  if (json) {
    std::cout << json_text(with_map_source(road_json(road, zone), source), 2) << "\n";
    return 0;
  }
  if (source) print_map_source(*source);
  std::printf("road      %s\n", road_label(road).c_str());
  std::printf("distance  %.2f m\n", road.distance_m);
  std::printf("closest   E %.2f N %.2f (UTM zone %d%s)\n", road.closest.easting_m,
              road.closest.northing_m, zone.zone, zone.northern ? "N" : "S");
  return 0;
}

}  // namespace

int NearestCommand::run() {
  if (query_.uses_set()) {
    std::optional<MapSet> set = open_set_or_report(query_.db_paths);
    if (!set) return 1;
    const auto road = set->nearest(query_.position(), max_distance_m_);
    if (!road.ok()) return report_error(road.status);
    return print_nearest(road->answer, set->map(road->map.index).info().zone, &road->map,
                         query_.json);
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<NearestRoad> road = map->nearest(query_.position(), max_distance_m_);
  if (!road.ok()) return query_.report_error(*map, road.status);
  return print_nearest(*road, map->info().zone, nullptr, query_.json);
}

}  // namespace roadcross::cli
