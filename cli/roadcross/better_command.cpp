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
}

int BetterCommand::run() {
  std::optional<Map> map = open_map_or_report(query_.db_path);
  if (!map) return 1;
  const Result<BetterPlaces> result = map->better_place(query_.position(), options_);
  if (!result.ok()) return query_.report_error(*map, result.status);
  if (query_.json) {
    const nlohmann::ordered_json out = better_places_json(*result, map->info().zone);
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  if (result->candidates.empty()) {
    std::printf("%s\n", result->reason.c_str());
    return 0;
  }
  std::printf("%-4s %9s %8s %-9s %-19s %s\n", "#", "walk (m)", "score", "crossing",
              "go to (UTM E, N)", "cross yaw (rad)");
  int rank = 1;
  for (const Candidate& c : result->candidates) {
    std::printf("%-4d %9.1f %8d %-9s %9.1f %9.1f %+8.3f\n", rank++, c.walking_distance_m, c.score,
                c.designated_crossing ? "zebra" : "-", c.point.easting_m, c.point.northing_m,
                c.crossing_heading_rad);
  }
  return 0;
}

}  // namespace roadcross::cli
