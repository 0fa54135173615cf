// Options shared by the query subcommands: the DB (or a set of maps) and one position.
#pragma once

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

#include "roadcross/map_set.hpp"
#include "roadcross/runtime.hpp"

namespace roadcross::cli {

struct QueryOptions {
  /// --db, repeatable: map files or directories of maps. One file is asked as a Map; more, or
  /// a directory, as a MapSet (answers then name the map that gave them).
  std::vector<std::string> db_paths;
  std::optional<double> lat_deg;
  std::optional<double> lon_deg;
  std::vector<double> utm;  ///< easting_m northing_m
  std::string utm_zone;     ///< --utm-zone, e.g. "33N"; empty: the map's zone
  std::optional<double> sigma_m;
  double region_probability = 0.95;
  bool json = false;

  /// Adds --db, --lat, --lon, --utm, --utm-zone, --sigma, --region-probability and --json to
  /// `command`.
  void add_to(CLI::App& command);
  /// The position given on the command line (CLI11 already ensured exactly one form, and that
  /// --utm-zone parses), with the circular uncertainty of --sigma when given.
  Position position() const;
  /// True when the query goes to a MapSet: several --db, or a directory.
  bool uses_set() const;
  /// The first --db (the one map when !uses_set()).
  const std::string& db_path() const { return db_paths.front(); }
  /// When --lat/--lon lie outside the map's extent but would lie inside it swapped, a sentence
  /// saying so; else nullopt.
  std::optional<std::string> swapped_lat_lon_hint(const Map& map) const;
  /// report_error, with the swapped-coordinates hint when it applies.
  int report_error(const Map& map, const Status& status) const;
};

/// Opens the DB or prints the runtime's message and returns nullopt.
std::optional<Map> open_map_or_report(const std::string& path);

/// Opens the set of maps or prints the runtime's message and returns nullopt.
std::optional<MapSet> open_set_or_report(const std::vector<std::string>& paths);

/// "map       PATH (id ID)" for the text answers of a set.
void print_map_source(const MapSource& source);

/// "Name (highway, OSM way W, segment S)" for the text answers.
std::string road_label(const NearestRoad& road);

/// Prints the runtime's error (on stderr, or as JSON under --json); returns the exit code 1.
int report_error(const Status& status);

}  // namespace roadcross::cli
