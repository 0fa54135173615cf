// Batch mode: for scripts and for checking a list of sites before a mission. Each input line is
// a JSON object {"op": "assess" | "better" | "heading" | "nearest", "lat": .., "lon": ..} or
// with "easting"/"northing"; optional "threshold", "valid_distance_m", "radius_m". Each output
// line is {"line": N, "ok": true, "result": {...}} or {"line": N, "ok": false, "error": "..."};
// a bad line never stops the batch.
#include <iostream>
#include <string>

#include "commands.hpp"
#include "json_output.hpp"

namespace roadcross::cli {
namespace {

Position position_of(const nlohmann::json& request) {
  if (request.contains("lat") || request.contains("lon")) {
    return Position::wgs84(request.at("lat").get<double>(), request.at("lon").get<double>());
  }
  return Position::utm(request.at("easting").get<double>(), request.at("northing").get<double>());
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

nlohmann::ordered_json handle(Map& map, const nlohmann::json& request) {
  const std::string op = request.value("op", "assess");
  const Position position = position_of(request);
  AssessOptions assess;
  if (request.contains("threshold")) assess.threshold = request.at("threshold").get<double>();
  if (request.contains("valid_distance_m"))
    assess.valid_distance_m = request.at("valid_distance_m").get<double>();
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

}  // namespace

BatchCommand::BatchCommand(CLI::App& parent) {
  app_ = parent.add_subcommand("batch",
                               "answer one JSON request per line of stdin, one JSON line each");
  app_->add_option("--db", db_path_, "roadcross GeoPackage")->required();
}

int BatchCommand::run() {
  std::optional<Map> map = open_map_or_report(db_path_);
  if (!map) return 1;
  std::string line;
  long number = 0;
  int failures = 0;
  while (std::getline(std::cin, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    nlohmann::ordered_json out;
    try {
      out = handle(*map, nlohmann::json::parse(line));
    } catch (const std::exception& e) {
      out["ok"] = false;
      out["error"] = std::string("line ") + std::to_string(number) + ": " + e.what();
      out["code"] = "invalid_request";
    }
    if (!out["ok"].get<bool>()) ++failures;
    nlohmann::ordered_json numbered;
    numbered["line"] = number;
    for (auto& [key, value] : out.items()) numbered[key] = value;
    std::cout << numbered.dump() << "\n";
  }
  return failures == 0 ? 0 : 3;  // 3: the batch ran, but some requests failed (see their lines)
}

}  // namespace roadcross::cli
