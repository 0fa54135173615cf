#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/monitor.hpp"

namespace roadcross::cli {
namespace {

std::string number_or_dash(const std::optional<double>& value, const char* format) {
  if (!value) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, *value);
  return text;
}

std::string int_or_dash(const std::optional<int>& value) {
  return value ? std::to_string(*value) : std::string("-");
}

/// The answer as text or JSON. `zone`: the answering map's UTM zone; `source` names the map of
/// a set that gave it (null for one map); `hint` a note on the position (swapped lat/lon).
int print_assessment(const Assessment& a, const geo::UtmZone& zone, const MapSource* source,
                     const std::optional<std::string>& hint, bool json);

}  // namespace

AssessCommand::AssessCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("assess", "is this a suitable place to cross, and why not");
  query_.add_to(*app_);
  app_->add_option("--valid-distance", options_.valid_distance_m,
                   "valid within this distance of a centreline, metres (default: the DB's)");
  app_->add_option("--threshold", options_.threshold,
                   "suitable when score + context >= this (default: the DB's)");
  app_->add_option("--max-kerb-height", options_.max_kerb_height_m,
                   "highest kerb the robot climbs, metres: a known higher kerb is KERB_TOO_HIGH "
                   "(default: the map profile's, 1 = no limit)")
      ->check(CLI::Range(0.0, 100.0));
}

int AssessCommand::run() {
  if (query_.uses_set()) {
    std::optional<MapSet> set = open_set_or_report(query_.db_paths);
    if (!set) return 1;
    const auto result = set->assess(query_.position(), options_);
    if (!result.ok()) return report_error(result.status);
    return print_assessment(result->answer, set->map(result->map.index).info().zone, &result->map,
                            std::nullopt, query_.json);
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<Assessment> result = map->assess(query_.position(), options_);
  if (!result.ok()) return query_.report_error(*map, result.status);
  std::optional<std::string> hint;
  if (!result->valid) hint = query_.swapped_lat_lon_hint(*map);
  return print_assessment(*result, map->info().zone, nullptr, hint, query_.json);
}

namespace {

int print_assessment(const Assessment& a, const geo::UtmZone& zone, const MapSource* source,
                     const std::optional<std::string>& hint, bool json) {
  if (json) {
    nlohmann::ordered_json out = with_map_source(assessment_json(a, zone), source);
    if (hint) out["hint"] = *hint;
    std::cout << json_text(out, 2) << "\n";
    return 0;
  }
  if (hint) std::fprintf(stderr, "roadcross: note: %s\n", hint->c_str());
  if (source) print_map_source(*source);
  const std::string name = a.road.name.empty() ? "(unnamed)" : a.road.name;
  std::printf("%s\n", a.suitable ? "SUITABLE place to cross"
                                 : (a.valid ? "NOT suitable here" : "NOT at a road"));
  std::printf("road        %s (%s, OSM way %lld), %.2f m away\n", name.c_str(),
              a.road.highway.c_str(), static_cast<long long>(a.road.osm_way_id), a.road.distance_m);
  std::printf("score       %s + context %s = %d (threshold %g)\n", int_or_dash(a.score).c_str(),
              int_or_dash(a.context_score).c_str(),
              a.score.value_or(0) + a.context_score.value_or(0), a.threshold);
  std::printf("rank        %s of 14   class %s   curvature %s (level %s, radius %s m)\n",
              int_or_dash(a.rank).c_str(), int_or_dash(a.class_cost).c_str(),
              int_or_dash(a.curvature_cost).c_str(), int_or_dash(a.curvature_level).c_str(),
              number_or_dash(a.radius_m, "%.0f").c_str());
  std::printf("junction    %s m along the road   designated crossing %s m\n",
              number_or_dash(a.junction_distance_m, "%.1f").c_str(),
              number_or_dash(a.crossing_distance_m, "%.1f").c_str());
  std::printf("terrain     %s, elevation cost %s of 9\n",
              a.landform ? ("landform " + *a.landform).c_str() : "no elevation data",
              int_or_dash(a.elevation_cost).c_str());
  std::printf("traffic     maxspeed %s km/h, %s lanes, %s m wide\n",
              number_or_dash(a.maxspeed_kmh, "%.0f").c_str(), int_or_dash(a.lanes).c_str(),
              number_or_dash(a.width_m, "%.1f").c_str());
  std::printf("sight       %s m forward, %s m backward, needs %s m\n",
              number_or_dash(a.sight_forward_m, "%.0f").c_str(),
              number_or_dash(a.sight_backward_m, "%.0f").c_str(),
              number_or_dash(a.required_sight_m, "%.0f").c_str());
  // Only where the map says something: most of today's maps say nothing here.
  if (a.kerb || a.kerb_height_m || a.crossing_island || a.pavement_far_side)
    std::printf(
        "kerb        %s, %s m high (robot climbs %g m)   island %s   pavement far side %s\n",
        a.kerb ? a.kerb->c_str() : "unknown", number_or_dash(a.kerb_height_m, "%.2f").c_str(),
        a.max_kerb_height_m, a.crossing_island ? (*a.crossing_island ? "yes" : "no") : "unknown",
        a.pavement_far_side ? (*a.pavement_far_side ? "yes" : "no") : "unknown");
  if (a.region) {
    const UncertaintyRegion& r = *a.region;
    std::printf(
        "region      %.0f %% within %.1f x %.1f m: %zu segment%s, %s, %.0f %% on suitable "
        "places, heading spread %.1f deg\n",
        100.0 * r.region_probability, r.semi_major_m, r.semi_minor_m, r.segment_ids.size(),
        r.segment_ids.size() == 1 ? "" : "s", r.same_road ? "one road" : "several roads",
        100.0 * r.suitable_share, geo::rad_to_deg(r.heading_spread_rad));
  }
  for (const std::string& code : a.reasons) {
    std::printf("  %-20s %s\n", code.c_str(), describe_reason(code));
  }
  if (!a.override_note.empty()) std::printf("  operator note: %s\n", a.override_note.c_str());
  return 0;
}

}  // namespace

}  // namespace roadcross::cli
