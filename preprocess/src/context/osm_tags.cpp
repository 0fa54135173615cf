#include "roadcross/preprocess/context/osm_tags.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>

namespace roadcross::preprocess {

namespace {

/// "Schrittgeschwindigkeit" / "walk": German courts read it as 4-7 km/h; the upper end is the
/// conservative choice (a faster road scores lower).
constexpr double kWalkKmh = 7.0;

// Sources: the national laws below, as summarised on the OSM wiki page "Default speed limits"
// (the page maxspeed=CC:zone values refer to). Passenger cars, no trailer, dry road.
constexpr std::array<ImplicitSpeed, 37> kImplicitSpeeds = {{
    {"CZ", "urban", 50, "CZ 361/2000 Sb. s. 18(4)"},
    {"CZ", "rural", 90, "CZ 361/2000 Sb. s. 18(3)"},
    {"CZ", "trunk", 110, "CZ 361/2000 Sb. s. 18(3): silnice pro motorova vozidla"},
    {"CZ", "motorway", 130, "CZ 361/2000 Sb. s. 18(3): dalnice"},
    {"CZ", "living_street", 20, "CZ 361/2000 Sb. s. 39(1): obytna zona"},
    {"CZ", "pedestrian_zone", 20, "CZ 361/2000 Sb. s. 39(2): pesi zona"},
    {"SK", "urban", 50, "SK 8/2009 Z. z. s. 16(3)"},
    {"SK", "rural", 90, "SK 8/2009 Z. z. s. 16(2)"},
    {"SK", "motorway", 130, "SK 8/2009 Z. z. s. 16(2): dialnica, rychlostna cesta"},
    {"SK", "living_street", 20, "SK 8/2009 Z. z. s. 60: obytna zona"},
    {"DE", "urban", 50, "StVO s. 3(3) no. 1: innerorts"},
    {"DE", "rural", 100, "StVO s. 3(3) no. 2c: ausserorts"},
    {"DE", "motorway", kNoLimitKmh,
     "no general limit (130 advisory, Autobahn-Richtgeschwindigkeits-VO)"},
    {"DE", "zone30", 30, "StVO s. 45(1c): Tempo 30-Zone"},
    {"DE", "zone20", 20, "StVO s. 45(1d): verkehrsberuhigter Geschaeftsbereich"},
    {"DE", "living_street", kWalkKmh, "StVO Anlage 3 Zeichen 325.1: Schrittgeschwindigkeit"},
    {"DE", "bicycle_road", 30, "StVO Anlage 2 Zeichen 244.1: Fahrradstrasse"},
    {"AT", "urban", 50, "StVO 1960 s. 20(2): Ortsgebiet"},
    {"AT", "rural", 100, "StVO 1960 s. 20(2): Freiland"},
    {"AT", "trunk", 100, "StVO 1960 s. 20(2): Autostrasse"},
    {"AT", "motorway", 130, "StVO 1960 s. 20(2): Autobahn"},
    {"AT", "living_street", kWalkKmh, "StVO 1960 s. 76b: Wohnstrasse, Schrittgeschwindigkeit"},
    {"AT", "zone30", 30, "StVO 1960 s. 52 a 11a: Zonenbeschraenkung 30"},
    {"PL", "urban", 50, "PL Prawo o ruchu drogowym art. 20(2): obszar zabudowany"},
    {"PL", "rural", 90, "PL Prawo o ruchu drogowym art. 20(3): poza obszarem zabudowanym"},
    {"PL", "expressway", 120,
     "PL Prawo o ruchu drogowym art. 20(3): droga ekspresowa dwujezdniowa"},
    {"PL", "motorway", 140, "PL Prawo o ruchu drogowym art. 20(3): autostrada"},
    {"PL", "living_street", 20, "PL Prawo o ruchu drogowym art. 20(1): strefa zamieszkania"},
    {"FR", "urban", 50, "FR Code de la route R413-3: en agglomeration"},
    {"FR", "rural", 80, "FR Code de la route R413-2 (decret 2018-487): hors agglomeration"},
    {"FR", "trunk", 110, "FR Code de la route R413-2: routes a chaussees separees"},
    {"FR", "motorway", 130, "FR Code de la route R413-2: autoroutes"},
    {"FR", "zone30", 30, "FR Code de la route R110-2: zone 30"},
    {"FR", "living_street", 20, "FR Code de la route R110-2: zone de rencontre"},
    {"MC", "urban", 50,
     "MC Code de la route, OS 1.691 (1957): the principality is one built-up area"},
    {"default", "urban", 50, "most common European value (all countries above)"},
    {"default", "rural", 90, "most common European value (CZ, SK, PL)"},
}};

// Rows every country inherits unless it has its own (see implicit_speed_kmh).
constexpr std::array<ImplicitSpeed, 5> kDefaultExtra = {{
    {"default", "motorway", 130, "most common European value (CZ, SK, AT, FR)"},
    {"default", "living_street", 20, "most common European value (CZ, SK, PL, FR)"},
    {"default", "pedestrian_zone", 20, "as living_street"},
    {"default", "zone30", 30, "the zone's name"},
    {"default", "zone20", 20, "the zone's name"},
}};

bool equal_nocase(std::string_view a, std::string_view b) noexcept {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::string_view trim(std::string_view s) noexcept {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

/// A leading decimal number (decimal point or comma) and the rest of the text after it.
std::optional<double> leading_number(std::string_view s, std::string_view& rest) {
  std::string text(s);
  std::size_t length = 0;
  while (length < text.size() && (std::isdigit(static_cast<unsigned char>(text[length])) ||
                                  text[length] == '.' || text[length] == ',')) {
    if (text[length] == ',') text[length] = '.';  // "6,5": decimal comma
    ++length;
  }
  if (length == 0) return std::nullopt;
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + length, value);
  if (ec != std::errc() || end != text.data() + length) return std::nullopt;
  rest = trim(s.substr(length));
  return value;
}

/// Splits "a;b;c" and applies `parse` to each part; the highest value, or nullopt if any part
/// is not understood.
template <typename T, typename Parse>
std::optional<T> highest_of_list(std::string_view value, Parse parse) {
  std::optional<T> best;
  while (true) {
    const std::size_t semicolon = value.find(';');
    const std::optional<T> part = parse(trim(value.substr(0, semicolon)));
    if (!part) return std::nullopt;
    best = best ? std::max(*best, *part) : *part;
    if (semicolon == std::string_view::npos) return best;
    value.remove_prefix(semicolon + 1);
  }
}

std::optional<double> single_maxspeed_kmh(std::string_view value, std::string_view country) {
  if (value.empty()) return std::nullopt;
  if (equal_nocase(value, "none")) return kNoLimitKmh;
  if (equal_nocase(value, "walk")) return kWalkKmh;
  if (equal_nocase(value, "signals") || equal_nocase(value, "variable")) return std::nullopt;
  if (std::isdigit(static_cast<unsigned char>(value.front()))) {
    std::string_view unit;
    const std::optional<double> number = leading_number(value, unit);
    if (!number || *number <= 0.0) return std::nullopt;
    if (unit.empty() || unit == "km/h" || unit == "kmh" || unit == "kph") return *number;
    if (unit == "mph") return *number * 1.609344;
    if (unit == "knots") return *number * 1.852;
    return std::nullopt;
  }
  const auto [zone_country, zone] = split_speed_zone(value);
  if (!zone.empty()) {
    // "DE:30" (zone:maxspeed) is a number with a country.
    std::string_view rest;
    if (const auto number = leading_number(zone, rest); number && rest.empty()) return *number;
    return implicit_speed_kmh(zone_country, zone);
  }
  // Unprefixed "urban" / "rural" (seen in Monaco): the zone of the extract's country.
  return implicit_speed_kmh(country, value);
}

bool is_major(std::string_view highway) noexcept {
  const std::string_view base = highway.substr(0, highway.find("_link"));
  return base == "motorway" || base == "trunk" || base == "primary" || base == "secondary";
}

bool is_motorway_or_trunk(std::string_view highway) noexcept {
  const std::string_view base = highway.substr(0, highway.find("_link"));
  return base == "motorway" || base == "trunk";
}

/// maxspeed from maxspeed, maxspeed:forward and maxspeed:backward (the highest understood).
/// Sets `tagged_but_bad` when one of them is present but not understood (or "signals").
std::optional<double> tagged_maxspeed_kmh(const Tags& tags, std::string_view country,
                                          bool& tagged_but_bad) {
  std::optional<double> best;
  for (std::string_view key : {"maxspeed", "maxspeed:forward", "maxspeed:backward"}) {
    const std::string_view value = tag_value(tags, key);
    if (value.empty()) continue;
    const std::optional<double> kmh = parse_maxspeed_kmh(value, country);
    if (!kmh) {
      tagged_but_bad = true;
      continue;
    }
    best = best ? std::max(*best, *kmh) : *kmh;
  }
  return best;
}

/// Implicit limit from source:maxspeed, zone:maxspeed or maxspeed:type ("CZ:urban").
std::optional<double> source_maxspeed_kmh(const Tags& tags, std::string_view country) {
  for (std::string_view key : {"source:maxspeed", "zone:maxspeed", "maxspeed:type"}) {
    const std::string_view value = tag_value(tags, key);
    if (value.empty() || value == "sign") continue;
    if (const auto kmh = parse_maxspeed_kmh(value, country)) return kmh;
  }
  return std::nullopt;
}

std::optional<int> tagged_lanes(const Tags& tags, bool oneway, bool& tagged_but_bad) {
  if (const std::string_view lanes = tag_value(tags, "lanes"); !lanes.empty()) {
    if (const auto n = parse_lanes(lanes)) return n;
    tagged_but_bad = true;
  }
  const std::string_view forward = tag_value(tags, "lanes:forward");
  const std::string_view backward = tag_value(tags, "lanes:backward");
  if (forward.empty() && backward.empty()) return std::nullopt;
  const auto f = parse_lanes(forward), b = parse_lanes(backward);
  const auto both = parse_lanes(tag_value(tags, "lanes:both_ways"));
  if (f && b) return *f + *b + both.value_or(0);
  if (oneway && (f || b)) return f ? *f : *b;
  tagged_but_bad = true;  // one direction only on a two-way road: the other is unknown
  return std::nullopt;
}

std::optional<double> tagged_width_m(const Tags& tags, bool& tagged_but_bad) {
  for (std::string_view key : {"width:carriageway", "width", "est_width"}) {
    const std::string_view value = tag_value(tags, key);
    if (value.empty()) continue;
    if (const auto w = parse_width_m(value)) return w;
    tagged_but_bad = true;
  }
  return std::nullopt;
}

}  // namespace

std::span<const ImplicitSpeed> implicit_speed_table() noexcept {
  static const auto all = [] {
    std::array<ImplicitSpeed, kImplicitSpeeds.size() + kDefaultExtra.size()> rows{};
    std::copy(kImplicitSpeeds.begin(), kImplicitSpeeds.end(), rows.begin());
    std::copy(kDefaultExtra.begin(), kDefaultExtra.end(), rows.begin() + kImplicitSpeeds.size());
    return rows;
  }();
  return all;
}

bool has_implicit_speeds(std::string_view country) noexcept {
  const auto rows = implicit_speed_table();
  return std::any_of(rows.begin(), rows.end(),
                     [&](const ImplicitSpeed& r) { return equal_nocase(r.country, country); });
}

std::optional<double> implicit_speed_kmh(std::string_view country, std::string_view zone) noexcept {
  const auto rows = implicit_speed_table();
  const auto find = [&](std::string_view c, std::string_view z) -> std::optional<double> {
    for (const ImplicitSpeed& row : rows) {
      if (equal_nocase(row.country, c) && equal_nocase(row.zone, z)) return row.kmh;
    }
    return std::nullopt;
  };
  // "zone30" is also written "zone:30" and "30_zone"... only the OSM wiki's spelling is read.
  if (const auto own = find(country, zone)) return own;
  // A trunk road without its own national row is limited like any road outside towns.
  if (equal_nocase(zone, "trunk")) {
    if (const auto rural = find(country, "rural")) return rural;
  }
  if (const auto fallback = find("default", zone)) return fallback;
  if (equal_nocase(zone, "trunk")) return find("default", "rural");
  return std::nullopt;
}

std::pair<std::string, std::string> split_speed_zone(std::string_view value) {
  value = trim(value);
  const std::size_t colon = value.find(':');
  if (colon != 2 || !std::isalpha(static_cast<unsigned char>(value[0])) ||
      !std::isalpha(static_cast<unsigned char>(value[1]))) {
    return {};
  }
  std::string country(value.substr(0, 2));
  for (char& c : country) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::string zone(trim(value.substr(3)));
  // "DE:zone:30" and "DE:zone30" are the same zone.
  if (zone.starts_with("zone:")) zone.erase(4, 1);
  return {country, zone};
}

std::string country_of_speed_tag(std::string_view value) {
  return split_speed_zone(value).first;
}

std::optional<double> parse_maxspeed_kmh(std::string_view value, std::string_view country) {
  value = trim(value);
  if (value.empty()) return std::nullopt;
  return highest_of_list<double>(
      value, [&](std::string_view part) { return single_maxspeed_kmh(part, country); });
}

std::optional<int> parse_lanes(std::string_view value) {
  value = trim(value);
  if (value.empty()) return std::nullopt;
  return highest_of_list<int>(value, [](std::string_view part) -> std::optional<int> {
    int n = 0;
    const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), n);
    if (ec != std::errc() || end != part.data() + part.size() || n < 1 || n > 20)
      return std::nullopt;
    return n;
  });
}

std::optional<double> parse_width_m(std::string_view value) {
  value = trim(value);
  std::string_view rest;
  const std::optional<double> number = leading_number(value, rest);
  if (!number) return std::nullopt;
  double metres = 0.0;
  if (rest.empty() || rest == "m" || rest == "metre" || rest == "metres" || rest == "meter" ||
      rest == "meters") {
    metres = *number;
  } else if (rest == "'" || rest == "ft" || rest == "feet") {
    metres = *number * 0.3048;
  } else if (rest.starts_with("'") || rest.starts_with("ft ")) {
    // Feet and inches: 20'6" or 6 ft 6 in.
    std::string_view inches_text = trim(rest.substr(rest.front() == '\'' ? 1 : 3));
    std::string_view unit;
    const std::optional<double> inches = leading_number(inches_text, unit);
    if (!inches || (unit != "\"" && unit != "in")) return std::nullopt;
    metres = *number * 0.3048 + *inches * 0.0254;
  } else {
    return std::nullopt;
  }
  if (!(metres > 0.0) || metres > 100.0) return std::nullopt;
  return metres;
}

int default_lanes(std::string_view highway, bool oneway) noexcept {
  if (is_motorway_or_trunk(highway)) return oneway ? 2 : 4;
  if (oneway) return 1;
  // Service roads and living streets are rarely marked and usually one car wide.
  if (highway == "service" || highway == "living_street") return 1;
  return 2;
}

std::string_view default_speed_zone(std::string_view highway, bool assume_urban) noexcept {
  const std::string_view base = highway.substr(0, highway.find("_link"));
  if (base == "motorway") return "motorway";
  if (base == "living_street") return "living_street";
  if (base == "trunk" && !assume_urban) return "trunk";
  return assume_urban ? "urban" : "rural";
}

WayContext way_context(const Tags& tags, std::string_view highway, bool oneway,
                       const ContextDefaults& defaults) {
  WayContext out;
  bool bad = false;
  std::optional<double> speed = tagged_maxspeed_kmh(tags, defaults.country, bad);
  if (!speed) speed = source_maxspeed_kmh(tags, defaults.country);
  if (bad) out.unparsed.emplace_back("maxspeed");
  if (!speed) {
    // Untagged, "signals" or not understood: the implicit limit of the class's zone.
    out.defaulted.emplace_back("maxspeed");
    speed =
        implicit_speed_kmh(defaults.country, default_speed_zone(highway, defaults.assume_urban));
  }
  out.maxspeed_kmh = speed.value_or(50.0);

  bad = false;
  const std::optional<int> lanes = tagged_lanes(tags, oneway, bad);
  if (bad) out.unparsed.emplace_back("lanes");
  if (!lanes) out.defaulted.emplace_back("lanes");
  out.lanes = lanes.value_or(default_lanes(highway, oneway));

  bad = false;
  const std::optional<double> width = tagged_width_m(tags, bad);
  if (bad) out.unparsed.emplace_back("width");
  if (!width) out.defaulted.emplace_back("width");
  const double lane_width_m =
      is_major(highway) ? defaults.major_lane_width_m : defaults.lane_width_m;
  out.width_m = width.value_or(out.lanes * lane_width_m);
  return out;
}

}  // namespace roadcross::preprocess
