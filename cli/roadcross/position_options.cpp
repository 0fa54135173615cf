#include "position_options.hpp"

#include <cmath>
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
  const CLI::Validator finite_positive(
      [](const std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value) || !(value > 0.0))
          return "must be a finite number > 0, got " + text;
        return {};
      },
      "SIGMA > 0");
  command
      .add_option("--sigma", sigma_m,
                  "the position's standard deviation, metres (> 0): answer over the region it "
                  "may be in (docs/runtime.md, \"Position uncertainty\")")
      ->check(finite_positive);
  command
      .add_option("--region-probability", region_probability,
                  "with --sigma: the probability the region holds, in (0, 1)")
      ->capture_default_str()
      ->check(CLI::Validator(
          [](const std::string& text) -> std::string {
            double value = 0.0;
            if (!CLI::detail::lexical_cast(text, value) || !(value > 0.0 && value < 1.0))
              return "must be in (0, 1), got " + text;
            return {};
          },
          "P in (0, 1)"));
  command.add_flag("--json", json, "print JSON instead of text");
}

Position QueryOptions::position() const {
  const Position fix =
      utm.empty() ? Position::wgs84(*lat_deg, *lon_deg) : Position::utm(utm[0], utm[1]);
  return sigma_m ? fix.with_sigma(*sigma_m, region_probability) : fix;
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
