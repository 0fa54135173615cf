#include <iostream>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "json_output.hpp"
#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/mapcheck/verify.hpp"

namespace roadcross::cli {

namespace {

/// CLI11 validator: a map_id is 64 lower-case hex digits.
CLI::Validator map_id_validator() {
  return CLI::Validator(
      [](std::string& text) {
        return mapcheck::is_map_id(text) ? std::string()
                                         : "not a map_id (64 lower-case hex digits): " + text;
      },
      "MAP_ID");
}

}  // namespace

VerifyCommand::VerifyCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "verify",
      "check a map file before use: SQLite integrity, schema, R*Tree, content against map_id; "
      "exit 0 when whole, 1 naming each problem");
  app_->add_option("--db", db_path_, "roadcross GeoPackage")->required();
  app_->add_option("--expect-id", expected_id_, "fail unless the map's map_id is this one")
      ->check(map_id_validator());
  app_->add_flag("--json", json_, "print the result as JSON (ok, map_id, problems)");
}

int VerifyCommand::run() {
  const mapcheck::VerifyResult result = mapcheck::verify_map(db_path_, expected_id_);
  if (json_) {
    nlohmann::ordered_json out;
    out["path"] = db_path_;
    out["ok"] = result.ok();
    out["map_id"] = result.stored_map_id.empty() ? nlohmann::ordered_json()
                                                 : nlohmann::ordered_json(result.stored_map_id);
    out["segment_count"] = result.segment_count;
    out["problems"] = result.problems;
    std::cout << json_text(out, 2) << "\n";
  } else if (result.ok()) {
    std::cout << db_path_ << ": ok, map_id " << result.stored_map_id << ", " << result.segment_count
              << " segments\n";
  } else {
    for (const std::string& problem : result.problems) {
      std::cerr << "roadcross verify: " << db_path_ << ": " << problem << "\n";
    }
  }
  return result.ok() ? 0 : 1;
}

}  // namespace roadcross::cli
