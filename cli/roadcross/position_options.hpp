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
  std::optional<double> sigma_m;
  double region_probability = 0.95;
  bool json = false;

  /// Adds --db, --lat, --lon, --utm, --sigma, --region-probability and --json to `command`.
  void add_to(CLI::App& command);
  /// The position given on the command line (CLI11 already ensured exactly one form), with
  /// the circular uncertainty of --sigma when given.
  Position position() const;
};

/// Opens the DB or prints the runtime's message and returns nullopt.
std::optional<Map> open_map_or_report(const std::string& path);

/// "Name (highway, OSM way W, segment S)" for the text answers.
std::string road_label(const NearestRoad& road);

/// Prints the runtime's error on stderr; returns the exit code 1.
int report_error(const Status& status);

}  // namespace roadcross::cli
