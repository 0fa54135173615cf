#include "position_options.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cli_conventions.hpp"
#include "roadcross/geo.hpp"

namespace roadcross::cli {

void QueryOptions::add_to(CLI::App& command) {
  command
      .add_option("--db", db_paths,
                  "roadcross GeoPackage built by roadcross-build; repeatable, or a directory of "
                  "maps: a set of maps, each position answered by the map that covers it")
      ->required()
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  auto* lat = command.add_option("--lat", lat_deg, "WGS84 latitude, degrees");
  auto* lon = command.add_option("--lon", lon_deg, "WGS84 longitude, degrees");
  auto* utm_option =
      command.add_option("--utm", utm, "UTM easting and northing in the DB's zone, metres")
          ->expected(2)
          ->type_name("E N");
  lat->needs(lon);
  lon->needs(lat);
  utm_option->excludes(lat)->excludes(lon);
  command
      .add_option("--utm-zone", utm_zone,
                  "the zone of --utm, e.g. 33N or 34S (default: the DB's zone; required with a "
                  "set of maps, which may span zones)")
      ->needs(utm_option);
  command.callback([this, &command] {
    if (utm.empty() && !lat_deg) {
      throw CLI::ValidationError(command.get_name(),
                                 "give a position with --lat/--lon or --utm E N");
    }
    if (!utm_zone.empty() && !parse_utm_zone(utm_zone)) {
      throw CLI::ValidationError("--utm-zone", "'" + utm_zone +
                                                   "' is not a UTM zone (1..60 with N or S, "
                                                   "e.g. 33N)");
    }
    if (!utm.empty() && utm_zone.empty() && uses_set()) {
      throw CLI::ValidationError("--utm",
                                 "a set of maps may span UTM zones: give --utm-zone "
                                 "with --utm, or the position as --lat/--lon");
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
  Position fix = Position::wgs84(lat_deg.value_or(0.0), lon_deg.value_or(0.0));
  if (!utm.empty()) {
    const auto zone = parse_utm_zone(utm_zone);
    fix = zone ? Position::utm(utm[0], utm[1], *zone) : Position::utm(utm[0], utm[1]);
  }
  return sigma_m ? fix.with_sigma(*sigma_m, region_probability) : fix;
}

bool QueryOptions::uses_set() const {
  std::error_code error;
  return db_paths.size() > 1 ||
         (db_paths.size() == 1 && std::filesystem::is_directory(db_paths.front(), error));
}

std::optional<MapSet> open_set_or_report(const std::vector<std::string>& paths) {
  Result<MapSet> set = MapSet::open(paths);
  if (!set.ok()) {
    std::cerr << "roadcross: " << set.status.message << "\n";
    return std::nullopt;
  }
  return std::move(*set.value);
}

void print_map_source(const MapSource& source) {
  std::printf("map       %s%s\n", source.path.c_str(),
              source.map_id.empty() ? "" : (" (id " + source.map_id + ")").c_str());
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
