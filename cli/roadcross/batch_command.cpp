// Batch mode: for scripts and for checking a list of sites before a mission. Each input line is
// a JSON object {"op": "assess" | "better" | "heading" | "nearest", "lat": .., "lon": ..} or
// with "easting"/"northing" (and "utm_zone": "33N", required with a set of maps); optional
// "threshold", "valid_distance_m", "max_kerb_height_m", "radius_m", and a position uncertainty:
// "sigma_m" (metres) or "covariance_enu_m2" ([ee, en, nn], m^2), with "region_probability"
// (default 0.95). Each output line is {"line": N, "ok": true, "result": {...}} or
// {"line": N, "ok": false, "error": "..."}; a bad line never stops the batch. With a set of maps
// (--db repeated, or a directory) each result has a "map" member naming the map that answered.
#include <iostream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "json_output.hpp"
#include "request_lines.hpp"

namespace roadcross::cli {
namespace {

/// The request's position without its uncertainty.
Position fix_of(const nlohmann::json& request) {
  if (request.contains("lat") || request.contains("lon")) {
    return Position::wgs84(request.at("lat").get<double>(), request.at("lon").get<double>());
  }
  const double easting_m = request.at("easting").get<double>();
  const double northing_m = request.at("northing").get<double>();
  if (request.contains("utm_zone")) {
    const std::string text = request.at("utm_zone").get<std::string>();
    const auto zone = parse_utm_zone(text);
    if (!zone) throw std::invalid_argument("utm_zone '" + text + "' is not a zone (e.g. 33N)");
    return Position::utm(easting_m, northing_m, *zone);
  }
  return Position::utm(easting_m, northing_m);
}

/// The request's position with its uncertainty (sigma_m or covariance_enu_m2), when it has one.
Position position_of(const nlohmann::json& request) {
  Position fix = fix_of(request);
  const double probability = request.value("region_probability", 0.95);
  if (request.contains("sigma_m")) {
    fix = fix.with_sigma(request.at("sigma_m").get<double>(), probability);
  } else if (request.contains("covariance_enu_m2")) {
    // [east_east, east_north, north_north] in true ENU, as a GNSS receiver reports it.
    const auto c = request.at("covariance_enu_m2").get<std::vector<double>>();
    if (c.size() != 3) {
      throw std::invalid_argument(
          "covariance_enu_m2 takes 3 numbers: east_east, east_north, north_north (m^2)");
    }
    fix = fix.with_uncertainty(PositionUncertainty::enu(c[0], c[1], c[2], probability));
  }
  return fix;
}

template <typename T, typename ToJson>
nlohmann::ordered_json answer(const Result<T>& result, ToJson&& to_json, const Map& map) {
  nlohmann::ordered_json out;
  out["ok"] = result.ok();
  if (result.ok()) {
    out["result"] = to_json(*result, map.info().zone);
  } else {
    out["error"] = result.status.message;
    out["code"] = to_string(result.status.code);
  }
  return out;
}

/// A set's answer: the map's answer with the map that gave it.
template <typename T, typename ToJson>
nlohmann::ordered_json answer(const Result<FromMap<T>>& result, ToJson&& to_json,
                              const MapSet& set) {
  nlohmann::ordered_json out;
  out["ok"] = result.ok();
  if (result.ok()) {
    const geo::UtmZone& zone = set.map(result->map.index).info().zone;
    out["result"] = with_map_source(to_json(result->answer, zone), &result->map);
  } else {
    out["error"] = result.status.message;
    out["code"] = to_string(result.status.code);
  }
  return out;
}

/// Answers one request from a Map or a MapSet (same calls, the set's answers name their map).
template <typename Maps>
nlohmann::ordered_json handle(Maps& map, const nlohmann::json& request) {
  const std::string op = request.value("op", "assess");
  const Position position = position_of(request);
  AssessOptions assess;
  if (request.contains("threshold")) assess.threshold = request.at("threshold").get<double>();
  if (request.contains("valid_distance_m"))
    assess.valid_distance_m = request.at("valid_distance_m").get<double>();
  if (request.contains("max_kerb_height_m"))
    assess.max_kerb_height_m = request.at("max_kerb_height_m").get<double>();
  if (op == "assess") return answer(map.assess(position, assess), assessment_json, map);
  if (op == "heading") return answer(map.road_heading(position), heading_json, map);
  if (op == "nearest") return answer(map.nearest(position), road_json, map);
  if (op == "better") {
    BetterPlaceOptions options;
    options.assess = assess;
    options.search_radius_m = request.value("radius_m", options.search_radius_m);
    return answer(map.better_place(position, options), better_places_json, map);
  }
  throw std::invalid_argument("unknown op '" + op + "' (assess, better, heading, nearest)");
}

/// The answer line to request line `number` (text `line`) from a Map or a MapSet; `failed` tells
/// whether the request failed.
template <typename Maps>
std::string answer_line(Maps& maps, const std::string& line, long number, bool& failed) {
  nlohmann::ordered_json out;
  try {
    out = handle(maps, nlohmann::json::parse(line));
  } catch (const std::exception& e) {
    out["ok"] = false;
    out["error"] = std::string("line ") + std::to_string(number) + ": " + e.what();
    out["code"] = "invalid_request";
  }
  failed = !out["ok"].get<bool>();
  nlohmann::ordered_json numbered;
  numbered["line"] = number;
  for (auto& [key, value] : out.items()) numbered[key] = value;
  // Text from the request or the map may be any bytes: replaced (U+FFFD), never fatal.
  return json_text(numbered);
}

/// Reads the requests of stdin and prints one answer line each; the exit code.
template <typename Maps>
int answer_lines(Maps& maps);

}  // namespace

std::string batch_answer(Map& map, const std::string& line, long number, bool& failed) {
  return answer_line(map, line, number, failed);
}

BatchCommand::BatchCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("batch",
                               "answer one JSON request per line of stdin, one JSON line each");
  app_->add_option("--db", db_paths_,
                   "roadcross GeoPackage; repeatable, or a directory of maps: a set of maps")
      ->required()
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

int BatchCommand::run() {
  QueryOptions paths;
  paths.db_paths = db_paths_;
  if (paths.uses_set()) {
    std::optional<MapSet> set = open_set_or_report(db_paths_);
    if (!set) return 1;
    return answer_lines(*set);
  }
  std::optional<Map> map = open_map_or_report(db_paths_.front());
  if (!map) return 1;
  return answer_lines(*map);
}

namespace {

template <typename Maps>
int answer_lines(Maps& maps) {
  std::string line;
  long number = 0;
  int failures = 0;
  while (std::getline(std::cin, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    bool failed = false;
    std::cout << answer_line(maps, line, number, failed) << "\n";
    if (failed) ++failures;
  }
  return failures == 0 ? 0 : 3;  // 3: the batch ran, but some requests failed (see their lines)
}

}  // namespace

}  // namespace roadcross::cli
