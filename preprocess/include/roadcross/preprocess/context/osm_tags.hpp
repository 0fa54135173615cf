// Parsing the OSM tags the context score reads (maxspeed, lanes, width) as real OSM data has
// them, and the implicit national speed limits that stand in for missing ones. Pure functions:
// no I/O, no state. An unparseable value is never an error here: the parser says "not
// understood" (std::nullopt) and the caller takes a documented default.
// docs/cost-model.md ("Context score") has the national table with its legal sources.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::preprocess {

/// maxspeed=none (no general limit, e.g. parts of the German Autobahn) is recorded as this
/// speed: above every posted limit, so it scores as the fastest road.
inline constexpr double kNoLimitKmh = 200.0;

/// One row of the implicit speed table: maxspeed=CZ:urban means 50 km/h.
struct ImplicitSpeed {
  std::string_view country;  ///< ISO 3166-1 alpha-2, or "default"
  std::string_view zone;     ///< "urban", "rural", "motorway", "trunk", "living_street", ...
  double kmh = 0.0;
  std::string_view source;  ///< the law (and article) that sets the limit
};

/// Every row of the table, in a stable order (for the docs and the tests).
std::span<const ImplicitSpeed> implicit_speed_table() noexcept;

/// Implicit limit of `zone` in `country` ("CZ", "de" ...); a zone the country's row set lacks
/// falls back to the "default" rows. nullopt for a zone nobody defines.
std::optional<double> implicit_speed_kmh(std::string_view country, std::string_view zone) noexcept;

/// True when `country` has its own rows in the table.
bool has_implicit_speeds(std::string_view country) noexcept;

/// Speed of one maxspeed-like value, km/h: "50", "50 km/h", "30 mph", "10 knots",
/// "CZ:urban", "urban" (in `country`), "walk", "none", "50;30" (the highest). nullopt for
/// "signals"/"variable" (no number in the data) and anything not understood.
std::optional<double> parse_maxspeed_kmh(std::string_view value, std::string_view country);

/// "CZ:urban" -> ("CZ", "urban"); also "CZ:zone30", "DE:zone:30". Empty when not of that form.
std::pair<std::string, std::string> split_speed_zone(std::string_view value);

/// Lane count: "2" -> 2, "2;3" -> 3 (the highest). nullopt unless 1..20 lanes.
std::optional<int> parse_lanes(std::string_view value);

/// Width in metres: "6", "6 m", "6.5m", "6,5", "20'", "20 ft", "20'6\"", "6 ft 6 in".
/// nullopt unless in (0, 100] m.
std::optional<double> parse_width_m(std::string_view value);

/// The inputs of the context score for one way, and which of them took a default.
struct WayContext {
  double maxspeed_kmh = 0.0;
  int lanes = 0;
  double width_m = 0.0;
  std::vector<std::string> defaulted;  ///< subset of {"maxspeed", "lanes", "width"}, in order
  /// Inputs with a tag present but not understood (or "signals"); a value from another tag
  /// may still have been used (maxspeed:backward when maxspeed is bad).
  std::vector<std::string> unparsed;
};

/// How to fill in what a way's tags do not say.
struct ContextDefaults {
  std::string country = "default";  ///< country of implicit limits for untagged ways
  bool assume_urban = true;         ///< untagged ways are inside a built-up area
  double lane_width_m = 3.0;        ///< per lane, minor roads
  double major_lane_width_m = 3.5;  ///< per lane, motorway/trunk/primary/secondary
};

/// Default lane count of a class: 1 when one-way (2 on motorway/trunk), otherwise 2
/// (4 on motorway/trunk, 1 on service roads and living streets).
int default_lanes(std::string_view highway, bool oneway) noexcept;

/// Implicit zone of an untagged way of this class ("motorway", "living_street", "urban"...).
std::string_view default_speed_zone(std::string_view highway, bool assume_urban) noexcept;

/// maxspeed, lanes and width of a way from its tags (see docs/cost-model.md for the order in
/// which tags are consulted).
WayContext way_context(const Tags& tags, std::string_view highway, bool oneway,
                       const ContextDefaults& defaults);

/// Country prefix ("CZ") of a maxspeed-like tag value, or empty.
std::string country_of_speed_tag(std::string_view value);

}  // namespace roadcross::preprocess
