#include "position_options.hpp"

#include <cstdio>
#include <iostream>

#include "cli_conventions.hpp"
#include "roadcross/geo.hpp"

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

std::optional<std::string> QueryOptions::swapped_lat_lon_hint(const Map& map) const {
  if (!lat_deg || !lon_deg) return std::nullopt;
  const MapInfo& info = map.info();
  const auto inside = [&](double lat, double lon) {
    if (!geo::is_valid_utm_lat_lon(lat, lon)) return false;
    try {
      const geo::UtmPoint p = geo::wgs84_to_utm(lat, lon, info.zone);
      return p.easting_m >= info.min_easting_m && p.easting_m <= info.max_easting_m &&
             p.northing_m >= info.min_northing_m && p.northing_m <= info.max_northing_m;
    } catch (const std::exception&) {
      return false;  // too far from the map's zone to project: not inside it either
    }
  };
  if (inside(*lat_deg, *lon_deg) || !inside(*lon_deg, *lat_deg)) return std::nullopt;
  char text[200];
  std::snprintf(text, sizeof text,
                "--lat %.7g --lon %.7g is outside the map, but --lat %.7g --lon %.7g is inside "
                "it: are latitude and longitude swapped?",
                *lat_deg, *lon_deg, *lon_deg, *lat_deg);
  return std::string(text);
}

int QueryOptions::report_error(const Map& map, const Status& status) const {
  if (const std::optional<std::string> hint = swapped_lat_lon_hint(map)) {
    return cli::report_error(Status{status.code, status.message + "; " + *hint});
  }
  return cli::report_error(status);
}

std::optional<Map> open_map_or_report(const std::string& path) {
  Result<Map> map = Map::open(path);
  if (!map.ok()) {
    report_error(map.status);
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
  print_error("roadcross", status.message, to_string(status.code));
  return 1;
}

}  // namespace roadcross::cli
