#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.hpp"
#include "json_output.hpp"
#include "request_lines.hpp"

namespace roadcross::cli {

TrackedVehicle parse_vehicle(const nlohmann::json& j, double now_s) {
  if (!j.is_object()) throw std::runtime_error("expected a JSON object");
  const auto number = [&j](const char* key) {
    if (!j.contains(key)) throw std::runtime_error(std::string("missing \"") + key + "\"");
    if (!j[key].is_number()) throw std::runtime_error(std::string("\"") + key + "\" not a number");
    return j[key].get<double>();
  };
  TrackedVehicle v;
  if (j.contains("east_m") || j.contains("north_m")) {
    v.frame = TrackedVehicle::Frame::robot_enu;
    v.x_m = number("east_m");
    v.y_m = number("north_m");
  } else {
    v.x_m = number("easting");
    v.y_m = number("northing");
  }
  v.vx_mps = number("vx_mps");
  v.vy_mps = number("vy_mps");
  if (j.contains("length_m")) v.length_m = number("length_m");
  if (j.contains("speed_uncertainty_mps"))
    v.speed_uncertainty_mps = number("speed_uncertainty_mps");
  v.time_s = now_s - (j.contains("age_s") ? number("age_s") : 0.0);
  return v;
}

namespace {

const char* reason_sentence(GapReason reason) {
  switch (reason) {
    case GapReason::clear:
      return "every vehicle passes outside the margin";
    case GapReason::vehicle_conflict:
      return "a vehicle would be in the robot's lane within the margin";
    case GapReason::blocked:
      return "a stopped vehicle stands in the crossing";
    case GapReason::insufficient_sight:
      return "the road is not seen far enough for its speed limit (sensor range, bend, building, "
             "crest or a junction close by): cross elsewhere";
    case GapReason::stale_track:
      return "a vehicle's track is too old to trust";
    case GapReason::gap_too_short:
      return "the next vehicle arrives within the HCM critical gap";
  }
  return "";
}

nlohmann::ordered_json decision_json(const GapDecision& d, const GapCrossing& c,
                                     const std::vector<int>& lines) {
  nlohmann::ordered_json out;
  out["decision"] = to_string(d.verdict);
  out["reason"] = to_string(d.reason);
  out["limiting_vehicle"] = d.limiting_vehicle;
  out["limiting_line"] =
      d.limiting_vehicle >= 0 ? nlohmann::ordered_json(lines[d.limiting_vehicle]) : nullptr;
  out["margin_s"] = or_null(d.margin_s);
  out["earliest_start_in_s"] = or_null(d.earliest_start_s);  // now = 0
  out["stage"] = d.stage;
  out["refuge_island"] = c.refuge_island;
  out["crossing_time_s"] = d.crossing_time_s;
  out["required_sight_m"] = d.required_sight_m;
  out["visible_road_m"] = d.visible_road_m;
  out["critical_gap_s"] = d.critical_gap_s;
  out["vehicles_counted"] = d.vehicles_counted;
  out["stale_tracks"] = d.stale_tracks;
  out["beyond_sensor_range"] = d.beyond_sensor_range;
  out["lanes"] = c.lanes;
  out["road_width_m"] = c.road_width_m;
  out["maxspeed_kmh"] = c.maxspeed_kmh;
  out["crossing_heading_rad"] = c.heading_rad;
  return out;
}

void print_decision(const GapDecision& d, const GapCrossing& c, const GapOptions& o,
                    const std::vector<int>& lines) {
  std::printf("%s  %s: %s\n", to_string(d.verdict), to_string(d.reason), reason_sentence(d.reason));
  if (d.limiting_vehicle >= 0) {
    std::printf("limiting    vehicle on input line %d\n", lines[d.limiting_vehicle]);
  } else {
    std::printf("limiting    %s\n",
                d.margin_s
                    ? "an unseen vehicle (beyond the visible road, or turning in at a junction)"
                    : "-");
  }
  const bool hcm = d.critical_gap_s > 0;
  if (d.margin_s && hcm) {
    std::printf("margin      %+.2f s (next arrival minus t_c)\n", *d.margin_s);
  } else if (d.margin_s) {
    std::printf("margin      %+.2f s (PET; needs %.2f s)\n", *d.margin_s, o.min_pet_s);
  }
  if (d.earliest_start_s) {
    std::printf("earliest    GO in %.2f s\n", *d.earliest_start_s);
  } else {
    std::printf("earliest    not under these predictions\n");
  }
  if (d.stage == 0) {
    std::printf("crossing    %.2f s over %d lane(s), %.1f m, %.0f km/h\n", d.crossing_time_s,
                c.lanes, c.road_width_m, c.maxspeed_kmh);
  } else {
    std::printf(
        "crossing    stage %d of 2 (refuge island): %.2f s over the %s lanes of %d, "
        "%.1f m, %.0f km/h\n",
        d.stage, d.crossing_time_s, d.stage == 1 ? "near" : "far", c.lanes, c.road_width_m,
        c.maxspeed_kmh);
  }
  if (hcm) {
    std::printf("critical    HCM t_c %.2f s\n", d.critical_gap_s);
  } else {
    std::printf("sight       needs %.0f m each way, sees %.0f m (sensor range %.0f m)\n",
                d.required_sight_m, d.visible_road_m, o.sensor_range_m);
  }
  std::printf("vehicles    %d counted, %d stale, %d beyond sensor range\n", d.vehicles_counted,
              d.stale_tracks, d.beyond_sensor_range);
}

}  // namespace

GapCommand::GapCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "gap",
      "GO or WAIT: tracked vehicles on stdin, one JSON object per line:\n"
      "  {\"easting\": E, \"northing\": N, \"vx_mps\": VX, \"vy_mps\": VY}  (UTM grid), or\n"
      "  {\"east_m\": X, \"north_m\": Y, ...} (robot ENU, origin at the robot);\n"
      "  optional \"length_m\", \"age_s\", \"speed_uncertainty_mps\"");
  query_.add_to(*app_);
  app_->add_option("--speed", robot_.speed_mps, "robot crossing speed, m/s")->capture_default_str();
  app_->add_option("--startup", robot_.startup_s, "robot start-up time, s")->capture_default_str();
  app_->add_option("--radius", robot_.radius_m, "robot half footprint, m")->capture_default_str();
  app_->add_option("--policy", policy_, "ours or hcm (HCM critical gap)")
      ->check(CLI::IsMember({"ours", "hcm"}))
      ->capture_default_str();
  app_->add_option("--min-pet", options_.min_pet_s, "required PET margin, s")
      ->capture_default_str();
  app_->add_option("--buffer", options_.safety_buffer_m, "corridor safety buffer, m")
      ->capture_default_str();
  app_->add_option("--sensor-range", options_.sensor_range_m, "road seen this far each way, m")
      ->capture_default_str();
  app_->add_option("--max-age", options_.max_track_age_s, "older tracks are stale, s")
      ->capture_default_str();
  app_->add_option("--hcm-start-clearance", hcm_.start_clearance_s,
                   "HCM t_s: start-up and clearance time, s")
      ->capture_default_str();
}

int GapCommand::run() {
  if (query_.uses_set()) {
    std::cerr << "roadcross gap: takes one map file (--db once); sets of maps are for "
                 "nearest, heading, assess, better and batch\n";
    return 2;
  }
  std::optional<Map> map = open_map_or_report(query_.db_path());
  if (!map) return 1;
  const Result<GapCrossing> crossing = gap_crossing(*map, query_.position());
  if (!crossing.ok()) return query_.report_error(*map, crossing.status);
  std::vector<TrackedVehicle> vehicles;
  std::vector<int> lines;  // input line of each vehicle, for the user
  std::string text;
  for (int line = 1; std::getline(std::cin, text); ++line) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    try {
      vehicles.push_back(parse_vehicle(nlohmann::json::parse(text), 0.0));
      lines.push_back(line);
    } catch (const std::exception& e) {
      return report_error(Status{StatusCode::invalid_argument,
                                 "stdin line " + std::to_string(line) + ": " + e.what()});
    }
  }
  const Result<GapDecision> d =
      policy_ == "hcm" ? hcm_gap_decision(*crossing, robot_, vehicles, 0.0, options_, hcm_)
                       : gap_decision(*crossing, robot_, vehicles, 0.0, options_);
  if (!d.ok()) return report_error(d.status);
  if (query_.json) {
    std::cout << json_text(decision_json(*d, *crossing, lines), 2) << "\n";
  } else {
    print_decision(*d, *crossing, options_, lines);
  }
  return 0;
}

}  // namespace roadcross::cli
