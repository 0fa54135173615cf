// The context score (thesis 4.2.4, docs/cost-model.md): how fast, wide and busy a road is from its
// OSM tags, plus a bonus near a designated crossing, and the operator overrides on top. Fills
// maxspeed_kmh, lanes, width_m, context_score, crossing_distance_m, context_defaulted and the
// override fields of every segment, and appends BUSY_ROAD (and OVERRIDE for no_crossing).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/context/crossings.hpp"
#include "roadcross/preprocess/context/overrides.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess {

struct ContextParameters {
  // Maximal speed (thesis): <= 30 km/h -> 3, <= 50 -> 2, <= 80 -> 1, faster -> 0.
  double speed_low_kmh = 30, speed_low_points = 3;
  double speed_mid_kmh = 50, speed_mid_points = 2;
  double speed_high_kmh = 80, speed_high_points = 1;
  // Number of lanes (thesis): 1 -> 5, 2 -> 4, 3 -> 2, 4 -> 1, more -> 0.
  double lanes1_points = 5, lanes2_points = 4, lanes3_points = 2, lanes4_points = 1;
  // Road width (thesis): <= 3.5 m -> 4, <= 4.5 -> 3, <= 5.5 -> 2, <= 6.5 -> 1, wider -> 0.
  double width1_m = 3.5, width1_points = 4, width2_m = 4.5, width2_points = 3;
  double width3_m = 5.5, width3_points = 2, width4_m = 6.5, width4_points = 1;
  // Road type (thesis): motorway -10, trunk -4, primary 1, secondary 2, tertiary 3. The
  // thesis names no other class; roadcross gives the quieter ones the tertiary value so that a
  // residential street does not score below a tertiary road (docs/cost-model.md).
  double motorway_points = -10, trunk_points = -4, primary_points = 1, secondary_points = 2;
  double tertiary_points = 3, minor_points = 3;
  /// Bonus for a designated crossing within crossing_distance_max_m along the road (thesis +10).
  double crossing_points = 10, crossing_distance_max_m = 5;
  /// BUSY_ROAD when the context score (after overrides) is below this.
  double busy_road_below = 5;
  /// Untagged ways are in a built-up area (1) or outside (0): picks CC:urban or CC:rural.
  double assume_urban = 1;
  /// Default carriageway width per lane, metres: minor roads, and motorway..secondary.
  double lane_width_m = 3.0, major_lane_width_m = 3.5;

  void describe(std::vector<ParameterSpec>& out);
};

/// Context score of one segment from its inputs (thesis eq. 4.10: the sum of the terms).
int context_score(double maxspeed_kmh, int lanes, double width_m, std::string_view highway,
                  bool near_designated_crossing, const ContextParameters& parameters) noexcept;

/// The country whose implicit speed limits fill untagged ways, and how it was chosen.
struct CountryChoice {
  std::string country;  ///< "CZ", ..., or "default"
  std::string how;      ///< "option", "tags" or "location"
};

/// `option` when not empty; else the most common country prefix of the road ways'
/// maxspeed-like tags ("CZ:urban"); else the country whose box holds the extract's centre;
/// else "default".
CountryChoice choose_country(const RoadNetwork& network, std::string_view option);

/// What the stage did, for the build summary and the DB.
struct ContextReport {
  CountryChoice country;
  std::vector<Crossing> crossings;
  std::uint64_t road_ways = 0;
  std::map<std::string, std::uint64_t> defaulted_ways;  ///< tag -> ways that took the default
  std::map<std::string, std::uint64_t> unparsed_ways;   ///< tag -> ways with a value not understood
  std::uint64_t override_segments = 0;                  ///< segments touched by an override
  std::vector<std::size_t> unmatched_overrides;         ///< feature indexes that touched nothing
  std::uint64_t busy_segments = 0;
  std::uint64_t kerb_segments = 0;    ///< segments with a known kerb height
  std::uint64_t island_segments = 0;  ///< segments at a crossing with a refuge island
  std::uint64_t pavement_sides_known = 0, pavement_sides = 0;  ///< piece sides, known / all
  /// Context scores by way index, without and with the crossing bonus: left by
  /// compute_way_context for finish_context, which empties it.
  struct WayScores {
    int away = 0;
    int near_crossing = 0;
  };
  std::vector<WayScores> way_scores;

  /// One line per tag ("maxspeed: default on 12 of 653 road ways (2 not understood)") and the
  /// crossing and override counts.
  std::vector<std::string> summary_lines() const;
};

/// The part of the stage that needs the road network: the country, every segment's speed
/// limit, lanes and width, the crossings and each way's two possible context scores. It reads
/// only what segmenting set, so the build runs it right after segmenting and frees the network
/// before the cost stages (a sixth of the memory at that point).
ContextReport compute_way_context(RoadGraph& graph, const RoadNetwork& network,
                                  const ContextParameters& parameters,
                                  std::string_view country_option);

/// The rest, after the other cost stages: the crossing distances and the context scores, then
/// the overrides (which may change any cost, so they come after all of them) and BUSY_ROAD.
/// `overrides` may be empty.
void finish_context(RoadGraph& graph, const ContextParameters& parameters,
                    const std::vector<Override>& overrides, ContextReport& report);

/// finish_context after assign_crossing_distances(graph, report.crossings) has run: the build
/// runs that search beside the geometry stage (it needs only the pieces' ends and lengths, and
/// writes only the segments' crossing distances).
void score_context(RoadGraph& graph, const ContextParameters& parameters,
                   const std::vector<Override>& overrides, ContextReport& report);

/// Both parts at once. `overrides` may be empty.
ContextReport compute_context(RoadGraph& graph, const RoadNetwork& network,
                              const ContextParameters& parameters, std::string_view country_option,
                              const std::vector<Override>& overrides);

}  // namespace roadcross::preprocess
