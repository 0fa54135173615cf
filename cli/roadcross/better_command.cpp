#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/monitor.hpp"

namespace roadcross::cli {

BetterCommand::BetterCommand(CLI::App& parent) {
  app_ =
      parent.add_subcommand("better", "better places to cross nearby, by walking along the road");
  query_.add_to(*app_);
  app_->add_option("--radius", options_.search_radius_m, "walking distance to search, metres")
      ->capture_default_str();
  app_->add_option("--max", options_.max_candidates, "at most this many places")
      ->capture_default_str();
  app_->add_option("--threshold", options_.assess.threshold,
                   "suitable when score + context >= this (default: the DB's)");
  app_->add_option("--max-kerb-height", options_.assess.max_kerb_height_m,
                   "highest kerb the robot climbs, metres: a known higher kerb is KERB_TOO_HIGH "
                   "(default: the map profile's, 1 = no limit)")
      ->check(CLI::Range(0.0, 100.0));
}

namespace {

/// The answer as text or JSON. `zone`: the answering map's UTM zone; `source` names the map of
/// a set that gave it (null for one map).
int print_better_places(const BetterPlaces& places, const geo::UtmZone& zone,
                        const MapSource* source, bool json) {
  if (json) {
    std::cout << json_text(with_map_source(better_places_json(places, zone), source), 2) << "\n";
    return 0;
  }
  if (source) print_map_source(*source);
  if (places.candidates.empty()) {
    std::printf("%s\n", places.reason.c_str());
    return 0;
  }
  std::printf("%-4s %9s %8s %-9s %-19s %s\n", "#", "walk (m)", "score", "crossing",
              "go to (UTM E, N)", "cross yaw (rad)");
  int rank = 1;
  for (const Candidate& c : places.candidates) {
    std::printf("%-4d %9.1f %8d %-9s %9.1f %9.1f %+8.3f\n", rank++, c.walking_distance_m, c.score,
                c.designated_crossing ? "zebra" : "-", c.point.easting_m, c.point.northing_m,
                c.crossing_heading_rad);
  }
  return 0;
}

}  // namespace

int BetterCommand::run() {
  if (query_.uses_set()) {
    std::optional<MapSet> set = open_set_or_report(query_.db_paths);
    if (!set) return 1;
    const auto result = set->better_place(query_.position(), options_);
    if (!result.ok()) return report_error(result.status);
    return print_better_places(result->answer, set->map(result->map.index).info().zone,
                               &result->map, query_.json);
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<BetterPlaces> result = map->better_place(query_.position(), options_);
  if (!result.ok()) return query_.report_error(*map, result.status);
  return print_better_places(*result, map->info().zone, nullptr, query_.json);
}

}  // namespace roadcross::cli
