#include "position_options.hpp"

#include <iostream>

namespace roadcross::cli {

void QueryOptions::add_to(CLI::App& command) {
  command.add_option("--db", db_path, "roadcross GeoPackage built by roadcross-build")->required();
  auto* lat = command.add_option("--lat", lat_deg, "WGS84 latitude, degrees");
  auto* lon = command.add_option("--lon", lon_deg, "WGS84 longitude, degrees");
  auto* utm_option =
      command.add_option("--utm", utm, "UTM easting and northing in the DB's zone, metres")
          ->expected(2)
          ->type_name("E N");
  lat->needs(lon);
  lon->needs(lat);
  utm_option->excludes(lat)->excludes(lon);
  command.callback([this, &command] {
    if (utm.empty() && !lat_deg) {
      throw CLI::ValidationError(command.get_name(),
                                 "give a position with --lat/--lon or --utm E N");
    }
  });
  command.add_flag("--json", json, "print JSON instead of text");
}

Position QueryOptions::position() const {
  if (!utm.empty()) return Position::utm(utm[0], utm[1]);
  return Position::wgs84(*lat_deg, *lon_deg);
}

std::optional<Map> open_map_or_report(const std::string& path) {
  Result<Map> map = Map::open(path);
  if (!map.ok()) {
    std::cerr << "roadcross: " << map.status.message << "\n";
    return std::nullopt;
  }
  return std::move(*map.value);
}

std::string road_label(const NearestRoad& road) {
  const std::string name = road.name.empty() ? "(unnamed)" : road.name;
  return name + " (" + road.highway + ", OSM way " + std::to_string(road.osm_way_id) +
         ", segment " + std::to_string(road.segment_id) + ")";
}

int report_error(const Status& status) {
  std::cerr << "roadcross: " << status.message << "\n";
  return 1;
}

}  // namespace roadcross::cli
