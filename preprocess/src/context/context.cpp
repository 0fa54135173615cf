#include "roadcross/preprocess/context/context.hpp"

#include <algorithm>
#include <array>
#include <future>
#include <limits>
#include <optional>

#include "roadcross/preprocess/context/osm_tags.hpp"
#include "roadcross/preprocess/context/overrides.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::preprocess {

void ContextParameters::describe(std::vector<ParameterSpec>& out) {
  const std::string s = "context";
  const auto points = [&](const char* name, double* value, const char* what) {
    out.push_back({s, name, value, -1000, 1000, true, what});
  };
  const auto limit = [&](const char* name, double* value, double max, const char* what) {
    out.push_back({s, name, value, 0, max, false, what});
  };
  limit("speed_low_kmh", &speed_low_kmh, 300,
        "speed limit at or below which speed_low_points apply, km/h (thesis 30)");
  points("speed_low_points", &speed_low_points,
         "points for a speed limit <= speed_low_kmh (thesis 3)");
  limit("speed_mid_kmh", &speed_mid_kmh, 300,
        "speed_mid_points at or below this limit, km/h (thesis 50)");
  points("speed_mid_points", &speed_mid_points,
         "points for a speed limit <= speed_mid_kmh (thesis 2)");
  limit("speed_high_kmh", &speed_high_kmh, 300,
        "speed_high_points at or below this limit, km/h (thesis 80)");
  points("speed_high_points", &speed_high_points,
         "points for a speed limit <= speed_high_kmh (thesis 1); faster roads 0");
  points("lanes1_points", &lanes1_points, "points for 1 lane (thesis 5)");
  points("lanes2_points", &lanes2_points, "points for 2 lanes (thesis 4)");
  points("lanes3_points", &lanes3_points, "points for 3 lanes (thesis 2)");
  points("lanes4_points", &lanes4_points, "points for 4 lanes (thesis 1); 5 or more lanes 0");
  limit("width1_m", &width1_m, 100,
        "width1_points at or below this carriageway width, metres (thesis 3.5)");
  points("width1_points", &width1_points, "points for a width <= width1_m (thesis 4)");
  limit("width2_m", &width2_m, 100, "width2_points at or below this width, metres (thesis 4.5)");
  points("width2_points", &width2_points, "points for a width <= width2_m (thesis 3)");
  limit("width3_m", &width3_m, 100, "width3_points at or below this width, metres (thesis 5.5)");
  points("width3_points", &width3_points, "points for a width <= width3_m (thesis 2)");
  limit("width4_m", &width4_m, 100, "width4_points at or below this width, metres (thesis 6.5)");
  points("width4_points", &width4_points,
         "points for a width <= width4_m (thesis 1); wider roads 0");
  points("motorway_points", &motorway_points,
         "points for motorway and motorway_link (thesis text -10, code -50)");
  points("trunk_points", &trunk_points, "points for trunk and trunk_link (thesis -4)");
  points("primary_points", &primary_points, "points for primary roads and links (thesis 1)");
  points("secondary_points", &secondary_points, "points for secondary roads and links (thesis 2)");
  points("tertiary_points", &tertiary_points, "points for tertiary roads and links (thesis 3)");
  points("minor_points", &minor_points,
         "points for unclassified, residential, living_street, service, road, busway (thesis: "
         "none, i.e. 0; roadcross 3 = tertiary)");
  points("crossing_points", &crossing_points,
         "bonus near a designated crossing (thesis text +10, code +100)");
  limit("crossing_distance_max_m", &crossing_distance_max_m, 1000,
        "the crossing bonus applies up to this distance along the road from the segment midpoint, "
        "metres");
  points("busy_road_below", &busy_road_below,
         "reason BUSY_ROAD when the context score is below this");
  out.push_back(
      {s, "assume_urban", &assume_urban, 0, 1, true,
       "1: ways without speed tags are in a built-up area (CC:urban), 0: outside (CC:rural)"});
  out.push_back({s, "lane_width_m", &lane_width_m, 1, 10, false,
                 "default lane width of minor roads when width is not tagged, metres"});
  out.push_back({s, "major_lane_width_m", &major_lane_width_m, 1, 10, false,
                 "default lane width of motorway, trunk, primary and secondary roads, metres"});
}

int context_score(double maxspeed_kmh, int lanes, double width_m, std::string_view highway,
                  bool near_designated_crossing, const ContextParameters& p) noexcept {
  double score = 0.0;
  if (maxspeed_kmh <= p.speed_low_kmh) {
    score += p.speed_low_points;
  } else if (maxspeed_kmh <= p.speed_mid_kmh) {
    score += p.speed_mid_points;
  } else if (maxspeed_kmh <= p.speed_high_kmh) {
    score += p.speed_high_points;
  }
  const std::array<double, 4> lane_points = {p.lanes1_points, p.lanes2_points, p.lanes3_points,
                                             p.lanes4_points};
  if (lanes >= 1 && lanes <= 4) score += lane_points[static_cast<std::size_t>(lanes - 1)];
  if (width_m <= p.width1_m) {
    score += p.width1_points;
  } else if (width_m <= p.width2_m) {
    score += p.width2_points;
  } else if (width_m <= p.width3_m) {
    score += p.width3_points;
  } else if (width_m <= p.width4_m) {
    score += p.width4_points;
  }
  const std::string_view base = highway.substr(0, highway.find("_link"));
  if (base == "motorway") {
    score += p.motorway_points;
  } else if (base == "trunk") {
    score += p.trunk_points;
  } else if (base == "primary") {
    score += p.primary_points;
  } else if (base == "secondary") {
    score += p.secondary_points;
  } else if (base == "tertiary") {
    score += p.tertiary_points;
  } else {
    score += p.minor_points;
  }
  if (near_designated_crossing) score += p.crossing_points;
  return static_cast<int>(score);
}

namespace {

/// How far beyond the carriageway's edge a separately mapped footway=sidewalk may run and still
/// be the road's pavement, metres: room for a verge or a parking lane, not for the next street.
constexpr double kSidewalkBeyondEdgeM = 8.0;

struct CountryBox {
  const char* country;
  double min_lat, max_lat, min_lon, max_lon;
};

// Bounding boxes (Natural Earth admin-0, rounded outwards), smallest or most specific first:
// they overlap near borders, so this is only a fallback when no tag names the country.
constexpr std::array<CountryBox, 7> kCountryBoxes = {{
    {"MC", 43.72, 43.76, 7.40, 7.44},
    {"CZ", 48.55, 51.06, 12.09, 18.86},
    {"SK", 47.73, 49.61, 16.83, 22.57},
    {"AT", 46.37, 49.02, 9.53, 17.16},
    {"PL", 49.00, 54.84, 14.12, 24.15},
    {"DE", 47.27, 55.06, 5.87, 15.04},
    {"FR", 41.33, 51.12, -5.14, 9.56},
}};

std::string country_from_tags(const RoadNetwork& network) {
  std::map<std::string, std::uint64_t> votes;
  for (const RoadWay& way : network.ways) {
    for (std::string_view key : {"maxspeed", "source:maxspeed", "zone:maxspeed", "maxspeed:type"}) {
      const std::string country = country_of_speed_tag(tag_value(way.tags, key));
      if (!country.empty() && has_implicit_speeds(country)) ++votes[country];
    }
  }
  std::string best;
  std::uint64_t best_votes = 0;
  for (const auto& [country, n] : votes) {  // ties: alphabetical first
    if (n > best_votes) best = country, best_votes = n;
  }
  return best;
}

std::string country_from_location(const RoadNetwork& network) {
  if (network.locations.empty()) return {};
  double min_lat = std::numeric_limits<double>::infinity(), max_lat = -min_lat;
  double min_lon = min_lat, max_lon = -min_lat;
  for (const NodeLocation& n : network.locations) {
    min_lat = std::min(min_lat, n.lat_deg), max_lat = std::max(max_lat, n.lat_deg);
    min_lon = std::min(min_lon, n.lon_deg), max_lon = std::max(max_lon, n.lon_deg);
  }
  const double lat = 0.5 * (min_lat + max_lat), lon = 0.5 * (min_lon + max_lon);
  for (const CountryBox& box : kCountryBoxes) {
    if (lat >= box.min_lat && lat <= box.max_lat && lon >= box.min_lon && lon <= box.max_lon) {
      return box.country;
    }
  }
  return {};
}

/// What a way's WayContext gives its segments.
struct SegmentContext {
  double maxspeed_kmh = 0.0;
  double width_m = 0.0;
  int lanes = 0;
  bool known = false;                      ///< computed (the way has segments)
  const std::string* defaulted = nullptr;  ///< the defaulted tags, joined and interned, or none
};

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ",") + item;
  return out;
}

}  // namespace

CountryChoice choose_country(const RoadNetwork& network, std::string_view option) {
  if (!option.empty()) return {std::string(option), "option"};
  if (std::string c = country_from_tags(network); !c.empty()) return {c, "tags"};
  if (std::string c = country_from_location(network); !c.empty()) return {c, "location"};
  return {"default", "location"};
}

std::vector<std::string> ContextReport::summary_lines() const {
  std::vector<std::string> lines;
  lines.push_back("implicit speed limits of " + country.country + " (chosen by " + country.how +
                  ")");
  for (const char* tag : {"maxspeed", "lanes", "width"}) {
    const auto d = defaulted_ways.find(tag);
    const auto u = unparsed_ways.find(tag);
    lines.push_back(std::string(tag) + ": default on " +
                    std::to_string(d == defaulted_ways.end() ? 0 : d->second) + " of " +
                    std::to_string(road_ways) + " road ways (" +
                    std::to_string(u == unparsed_ways.end() ? 0 : u->second) +
                    " with a value not understood)");
  }
  std::uint64_t nodes = 0, designated = 0;
  for (const Crossing& c : crossings) {
    nodes += c.osm_type == "node" ? 1 : 0;
    designated += c.kind.designated ? 1 : 0;
  }
  lines.push_back("crossings: " + std::to_string(crossings.size()) + " (" + std::to_string(nodes) +
                  " nodes, " + std::to_string(crossings.size() - nodes) + " from crossing ways), " +
                  std::to_string(designated) + " designated");
  lines.push_back("kerbs: a known kerb height on " + std::to_string(kerb_segments) +
                  " segments, a refuge island on " + std::to_string(island_segments) +
                  "; pavement known on " + std::to_string(pavement_sides_known) + " of " +
                  std::to_string(pavement_sides) + " road sides");
  lines.push_back("BUSY_ROAD on " + std::to_string(busy_segments) + " segments");
  if (override_segments > 0 || !unmatched_overrides.empty()) {
    lines.push_back("overrides touched " + std::to_string(override_segments) + " segments");
  }
  for (std::size_t f : unmatched_overrides) {
    lines.push_back("warning: override feature " + std::to_string(f) + " touches no segment");
  }
  return lines;
}

ContextReport compute_way_context(RoadGraph& graph, const RoadNetwork& network,
                                  const ContextParameters& p, std::string_view country_option) {
  ContextReport report;
  report.country = choose_country(network, country_option);
  const ContextDefaults defaults{report.country.country, p.assume_urban != 0.0, p.lane_width_m,
                                 p.major_lane_width_m};
  // Per way, from the oneway flag segmentation already derived (ways without segments are
  // not counted: nothing of them reaches the DB). Only what the segments take is kept (the
  // tag lists of every way would cost ~200 bytes a way beside the road network).
  std::vector<SegmentContext> ways(network.ways.size());
  for (const Segment& s : graph.segments) {
    const std::size_t way_index = graph.pieces[s.piece_index].way_index;
    SegmentContext& w = ways[way_index];
    if (w.known) continue;
    const RoadWay& way = network.ways[way_index];
    const WayContext context = way_context(way.tags, way.highway, s.oneway, defaults);
    for (const std::string& tag : context.defaulted) ++report.defaulted_ways[tag];
    for (const std::string& tag : context.unparsed) ++report.unparsed_ways[tag];
    ++report.road_ways;
    w = {context.maxspeed_kmh, context.width_m, context.lanes, true,
         context.defaulted.empty() ? nullptr : graph.text.intern(join(context.defaulted))};
  }

  // The crossings with their kerbs and the sidewalks only read the pieces' lines and write
  // apart (graph.kerbs; each piece's sidewalks): the crossings' serial search runs on a thread
  // of its own beside the sidewalks' grid and per-piece search.
  std::future<std::vector<Crossing>> crossings = std::async(std::launch::async, [&] {
    std::vector<Crossing> found = find_crossings(network, graph);
    assign_kerbs(graph, network, found, p.crossing_distance_max_m);
    return found;
  });
  assign_sidewalks(graph, network, kSidewalkBeyondEdgeM);
  report.crossings = crossings.get();
  for (const auto& [index, facts] : graph.kerbs) {
    report.kerb_segments += facts.kerb_height_m ? 1 : 0;
    report.island_segments += facts.island.value_or(false) ? 1 : 0;
  }
  for (const RoadPiece& piece : graph.pieces) {
    report.pavement_sides_known += (piece.sidewalks.left ? 1 : 0) + (piece.sidewalks.right ? 1 : 0);
  }
  report.pavement_sides = 2 * graph.pieces.size();
  // The score depends on the segment only through its way (the highway is the way's) and
  // whether a crossing is near: both scores are kept per way, and finish_context picks one
  // once the crossing distances are known (their search runs after the network is freed).
  report.way_scores.resize(network.ways.size());
  for (RoadPiece& piece : graph.pieces) {
    const SegmentContext& w = ways[piece.way_index];
    piece.maxspeed_kmh = w.maxspeed_kmh;
    piece.lanes = w.lanes;
    piece.width_m = w.width_m;
  }
  // A way's segments run in a row and share their notes before and after: the note table's
  // hash lookup only when either changes. (The highway, and so the scores, are the way's.)
  std::size_t last_way = std::numeric_limits<std::size_t>::max();
  std::uint32_t last_notes = 0, last_result = 0;
  for (Segment& s : graph.segments) {
    const std::size_t way_index = graph.pieces[s.piece_index].way_index;
    const SegmentContext& w = ways[way_index];
    if (way_index != last_way || s.notes != last_notes) {
      last_notes = s.notes;
      graph.set_context_defaulted(s, w.defaulted);
      last_result = s.notes;
      if (way_index != last_way) {
        report.way_scores[way_index] = {
            context_score(w.maxspeed_kmh, w.lanes, w.width_m, graph.highway(s), false, p),
            context_score(w.maxspeed_kmh, w.lanes, w.width_m, graph.highway(s), true, p)};
      }
      last_way = way_index;
    } else {
      s.notes = last_result;
    }
  }
  return report;
}

void finish_context(RoadGraph& graph, const ContextParameters& p,
                    const std::vector<Override>& overrides, ContextReport& report) {
  assign_crossing_distances(graph, report.crossings);
  score_context(graph, p, overrides, report);
}

void score_context(RoadGraph& graph, const ContextParameters& p,
                   const std::vector<Override>& overrides, ContextReport& report) {
  for (Segment& s : graph.segments) {
    const ContextReport::WayScores& scores =
        report.way_scores[graph.pieces[s.piece_index].way_index];
    // The epsilon keeps a crossing exactly at the limit (a node between two 10 m segments is
    // 5 m from both midpoints) from missing its bonus to rounding.
    const bool near =
        s.crossing_distance_m && *s.crossing_distance_m <= p.crossing_distance_max_m + 1e-6;
    s.context_score = near ? scores.near_crossing : scores.away;
  }
  std::vector<ContextReport::WayScores>().swap(report.way_scores);
  const std::vector<std::uint64_t> touched = apply_overrides(graph, overrides);
  for (std::size_t i = 0; i < touched.size(); ++i) {
    report.override_segments += touched[i];
    if (touched[i] == 0) report.unmatched_overrides.push_back(overrides[i].feature_index);
  }
  for (Segment& s : graph.segments) {
    if (*s.context_score < p.busy_road_below) {
      s.reasons.add("BUSY_ROAD");
      ++report.busy_segments;
    }
  }
}

ContextReport compute_context(RoadGraph& graph, const RoadNetwork& network,
                              const ContextParameters& p, std::string_view country_option,
                              const std::vector<Override>& overrides) {
  ContextReport report = compute_way_context(graph, network, p, country_option);
  finish_context(graph, p, overrides, report);
  return report;
}

}  // namespace roadcross::preprocess
