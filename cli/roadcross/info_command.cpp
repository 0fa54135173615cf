#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/schema/schema.hpp"

namespace roadcross::cli {

InfoCommand::InfoCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "info", "show a map's UTM zone, extent, segment count, parameters and inputs");
  // --db like every other subcommand; the bare path (the older form) still works.
  CLI::Option* db = app_->add_option("--db", db_path_, "roadcross GeoPackage");
  CLI::Option* positional =
      app_->add_option("map", positional_path_, "roadcross GeoPackage (same as --db)");
  db->excludes(positional);
  app_->callback([this] {
    if (db_path_.empty() && positional_path_.empty()) {
      throw CLI::ValidationError("info", "give the map with --db MAP");
    }
    if (db_path_.empty()) db_path_ = positional_path_;
  });
  app_->add_flag("--json", json_, "print JSON instead of text");
  app_->footer("Example:\n  roadcross info --db prague.gpkg --json");
}

int InfoCommand::run() {
  const std::optional<Map> map = open_map_or_report(db_path_);
  if (!map) return 1;
  const MapInfo& info = map->info();
  if (json_) {
    nlohmann::ordered_json out;
    out["path"] = info.path;
    out["schema_version"] = info.schema_version;
    out["tool_version"] = info.tool_version;
    out["map_id"] =
        info.map_id.empty() ? nlohmann::ordered_json() : nlohmann::ordered_json(info.map_id);
    out["osm_timestamp"] = info.osm_timestamp.empty() ? nlohmann::ordered_json()
                                                      : nlohmann::ordered_json(info.osm_timestamp);
    out["utm_zone"] = info.zone.zone;
    out["utm_northern"] = info.zone.northern;
    out["epsg"] = info.epsg;
    out["segment_count"] = info.segment_count;
    out["extent_utm_m"] = {info.min_easting_m, info.min_northing_m, info.max_easting_m,
                           info.max_northing_m};
    // The UTM box's corners in latitude/longitude: south-west and north-east (the box in
    // degrees that holds the map is a little larger where the grid is rotated).
    nlohmann::ordered_json south_west =
        lat_lon_json(info.zone, PlanePoint{info.min_easting_m, info.min_northing_m});
    nlohmann::ordered_json north_east =
        lat_lon_json(info.zone, PlanePoint{info.max_easting_m, info.max_northing_m});
    out["extent_lat_lon_deg"] = {south_west[0], south_west[1], north_east[0], north_east[1]};
    // Built in one pass: the rows come sorted with unique keys (the table's primary key), and
    // inserting key by key would search the ordered object each time (quadratic in the rows).
    out["metadata"] = nlohmann::ordered_json::object_t(info.metadata.begin(), info.metadata.end());
    std::cout << json_text(out, 2) << "\n";
    return 0;
  }
  std::printf("file            %s\n", info.path.c_str());
  std::printf("schema version  %d (written by roadcross-build %s)\n", info.schema_version,
              info.tool_version.c_str());
  std::printf("map id          %s\n", info.map_id.empty()
                                          ? "(none: built before map ids, rebuild it)"
                                          : info.map_id.c_str());
  std::printf("OSM data as of  %s\n", info.osm_timestamp.empty()
                                          ? "(unknown: the OSM input had no timestamps)"
                                          : info.osm_timestamp.c_str());
  std::printf("CRS             WGS 84 / UTM zone %d%s (EPSG:%d)\n", info.zone.zone,
              info.zone.northern ? "N" : "S", info.epsg);
  std::printf("segments        %lld\n", static_cast<long long>(info.segment_count));
  std::printf("extent          E %.1f .. %.1f, N %.1f .. %.1f (%.2f x %.2f km)\n",
              info.min_easting_m, info.max_easting_m, info.min_northing_m, info.max_northing_m,
              (info.max_easting_m - info.min_easting_m) / 1000.0,
              (info.max_northing_m - info.min_northing_m) / 1000.0);
  std::printf("metadata\n");
  // The per-column content digests (what roadcross verify checks) are summed up in one line.
  int content_digests = 0;
  for (const auto& [key, value] : info.metadata) {
    if (key.starts_with(schema::meta::kContentDigestPrefix)) {
      ++content_digests;
      continue;
    }
    std::printf("  %-28s %s\n", key.c_str(), value.c_str());
  }
  if (content_digests > 0) {
    std::printf("  %-28s %d column digests (roadcross verify checks them; --json lists them)\n",
                "content.*", content_digests);
  }
  return 0;
}

}  // namespace roadcross::cli
