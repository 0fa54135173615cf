// Options shared by the query subcommands: the DB and one position.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "roadcross/runtime.hpp"

namespace roadcross::cli {

struct QueryOptions {
  std::string db_path;
  std::optional<double> lat_deg;
  std::optional<double> lon_deg;
  std::vector<double> utm;  ///< easting_m northing_m
  bool json = false;

  /// Adds --db, --lat, --lon, --utm and --json to `command`.
  void add_to(CLI::App& command);
  /// The position given on the command line (CLI11 already ensured exactly one form).
  Position position() const;
  /// When --lat/--lon lie outside the map's extent but would lie inside it swapped, a sentence
  /// saying so; else nullopt.
  std::optional<std::string> swapped_lat_lon_hint(const Map& map) const;
  /// report_error, with the swapped-coordinates hint when it applies.
  int report_error(const Map& map, const Status& status) const;
};

/// Opens the DB or prints the runtime's message and returns nullopt.
std::optional<Map> open_map_or_report(const std::string& path);

/// "Name (highway, OSM way W, segment S)" for the text answers.
std::string road_label(const NearestRoad& road);

/// Prints the runtime's error (on stderr, or as JSON under --json); returns the exit code 1.
int report_error(const Status& status);

}  // namespace roadcross::cli
