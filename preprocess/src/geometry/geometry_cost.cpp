#include "roadcross/preprocess/geometry/geometry_cost.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include "roadcross/preprocess/geometry/curvature.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/graph/strokes.hpp"

namespace roadcross::preprocess {

void GeometryParameters::describe(std::vector<ParameterSpec>& out) {
  const std::string s = "geometry";
  out.push_back({s, "class_cost_primary", &class_cost_primary, 0, 10, true,
                 "class cost of primary roads (and motorway, trunk, links)"});
  out.push_back({s, "class_cost_secondary", &class_cost_secondary, 0, 10, true,
                 "class cost of secondary roads"});
  out.push_back({s, "class_cost_tertiary", &class_cost_tertiary, 0, 10, true,
                 "class cost of tertiary roads and busways"});
  out.push_back({s, "class_cost_minor", &class_cost_minor, 0, 10, true,
                 "class cost of residential, living_street, service and road"});
  out.push_back({s, "class_cost_unclassified", &class_cost_unclassified, 0, 10, true,
                 "class cost of unclassified roads"});
  out.push_back({s, "near_junction_m", &near_junction_m, 0, 1000, false,
                 "NEAR_JUNCTION when the junction along the road is closer, metres"});
  out.push_back({s, "resample_spacing_m", &resample_spacing_m, 1, 1000, false,
                 "largest spacing of curvature samples along the road, metres (thesis 20)"});
  out.push_back({s, "curvature_baseline_m", &curvature_baseline_m, 0.5, 200, false,
                 "shortest arm of the curvature triangle, metres"});
  out.push_back({s, "curvature_max_arm_m", &curvature_max_arm_m, 1, 1000, false,
                 "longest arm of the curvature triangle, metres (sparse vertices)"});
  out.push_back({s, "straight_radius_m", &straight_radius_m, 100, 1e6, false,
                 "radius of a straight line, metres (thesis 10000)"});
  out.push_back({s, "level4_radius_m", &level4_radius_m, 0, 1e5, false,
                 "curvature level 4 below this radius, metres"});
  out.push_back({s, "level3_radius_m", &level3_radius_m, 0, 1e5, false,
                 "curvature level 3 below this radius, metres"});
  out.push_back({s, "level2_radius_m", &level2_radius_m, 0, 1e5, false,
                 "curvature level 2 below this radius, metres"});
  out.push_back({s, "level1_radius_m", &level1_radius_m, 0, 1e5, false,
                 "curvature level 1 below this radius, metres"});
  for (std::size_t level = 0; level < level_weight.size(); ++level) {
    out.push_back({s, "level" + std::to_string(level) + "_weight", &level_weight[level], 0, 1000,
                   false,
                   "weight of curvature level " + std::to_string(level) + " in the windowed cost"});
  }
  out.push_back({s, "window_half_length_m", &window_half_length_m, 0, 10000, false,
                 "curvature window: this far along the road each way, metres"});
  out.push_back({s, "own_segment_weight", &own_segment_weight, 0, 1000, false,
                 "the segment itself counts this many times in its window"});
  out.push_back({s, "sharp_bend_radius_m", &sharp_bend_radius_m, 0, 1e5, false,
                 "SHARP_BEND below this radius, metres"});
}

void GeometryParameters::validate_relations() const {
  // Levels are tested from 4 down to 1, so a limit below the one before it empties its level.
  const std::pair<const char*, double> limits[] = {{"level4_radius_m", level4_radius_m},
                                                   {"level3_radius_m", level3_radius_m},
                                                   {"level2_radius_m", level2_radius_m},
                                                   {"level1_radius_m", level1_radius_m}};
  for (std::size_t i = 1; i < std::size(limits); ++i) {
    if (limits[i].second < limits[i - 1].second) {
      throw ParameterError(std::string("geometry.") + limits[i].first + " (" +
                           format_number(limits[i].second) + ") must not be below geometry." +
                           limits[i - 1].first + " (" + format_number(limits[i - 1].second) + ")");
    }
  }
}

int class_cost(std::string_view highway, const GeometryParameters& p) noexcept {
  const std::string_view base = highway.substr(0, highway.find("_link"));
  double cost = 0;
  if (base == "motorway" || base == "trunk" || base == "primary") {
    cost = p.class_cost_primary;
  } else if (base == "secondary") {
    cost = p.class_cost_secondary;
  } else if (base == "tertiary" || base == "busway") {
    cost = p.class_cost_tertiary;
  } else if (base == "residential" || base == "living_street" || base == "service" ||
             base == "road") {
    cost = p.class_cost_minor;
  } else if (base == "unclassified") {
    cost = p.class_cost_unclassified;
  }
  return static_cast<int>(cost);
}

int curvature_level(double radius_m, bool at_junction, const GeometryParameters& p) noexcept {
  if (at_junction) return 5;
  if (radius_m < p.level4_radius_m) return 4;
  if (radius_m < p.level3_radius_m) return 3;
  if (radius_m < p.level2_radius_m) return 2;
  if (radius_m < p.level1_radius_m) return 1;
  return 0;
}

namespace {

bool is_junction(const RoadGraph& graph, std::int64_t node) {
  const auto it = graph.degree.find(node);
  return it != graph.degree.end() && it->second >= 3;
}

/// Shortest distance along the road from every graph node to a junction (multi-source
/// Dijkstra over the pieces), by the node's position in `nodes`; infinity where none is
/// reachable.
std::vector<double> distance_to_junction(const RoadGraph& graph, const Incidences& nodes) {
  std::vector<double> distance(nodes.node_count(), std::numeric_limits<double>::infinity());
  // Entries (distance, node position); positions are in node id order, so ties pop by id.
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (std::size_t n = 0; n < nodes.node_count(); ++n) {
    if (nodes.at_index(n).size() >= 3) {  // the node's degree: its piece ends
      distance[n] = 0.0;
      queue.push({0.0, n});
    }
  }
  while (!queue.empty()) {
    const auto [d, n] = queue.top();
    queue.pop();
    if (d > distance[n]) continue;
    for (const Incidence& end : nodes.at_index(n)) {
      const RoadPiece& piece = graph.pieces[end.piece];
      const std::size_t next = nodes.index_of(end.at_end ? piece.from_node_id : piece.to_node_id);
      const double candidate = d + piece.length_m;
      if (candidate < distance[next]) {
        distance[next] = candidate;
        queue.push({candidate, next});
      }
    }
  }
  return distance;
}

void assign_junction_distances(RoadGraph& graph, const GeometryParameters& p) {
  const Incidences nodes(graph);
  const std::vector<double> distance = distance_to_junction(graph, nodes);
  const auto at = [&](std::int64_t node) { return distance[nodes.index_of(node)]; };
  for (const RoadPiece& piece : graph.pieces) {
    const double from_end = at(piece.from_node_id), to_end = at(piece.to_node_id);
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      Segment& s = graph.segments[piece.first_segment + k];
      // Measured from the segment's midpoint: where a robot crossing "at this segment" stands.
      const double mid = graph.offset_in_piece_m(s) + 0.5 * graph.length_m(s);
      const double d = std::min(mid + from_end, piece.length_m - mid + to_end);
      if (std::isfinite(d)) {
        s.junction_distance_m = d;
        if (d < p.near_junction_m) s.reasons.add("NEAR_JUNCTION");
      }
    }
  }
}

/// Radius at the curvature points nearest to stroke position `at`: the radius of the nearest
/// point (so a segment between points takes the bend of the closer one).
double radius_near(const std::vector<double>& positions, const std::vector<double>& radii,
                   double at) {
  const auto it = std::lower_bound(positions.begin(), positions.end(), at);
  if (it == positions.begin()) return radii.front();
  if (it == positions.end()) return radii.back();
  const std::size_t j = static_cast<std::size_t>(it - positions.begin());
  return (at - positions[j - 1] <= positions[j] - at) ? radii[j - 1] : radii[j];
}

void assign_radii(RoadGraph& graph, const Stroke& stroke, const GeometryParameters& p) {
  // The OSM vertices carry the curvature; the points inserted every <= resample_spacing_m are
  // straight and only keep a bend's radius from spreading along a long edge.
  const RadiusProfile profile = radius_profile(
      stroke.points,
      {p.curvature_baseline_m, p.straight_radius_m, stroke.closed, p.curvature_max_arm_m},
      p.resample_spacing_m);
  const std::vector<double>& positions = profile.position_m;
  const std::vector<double>& radii = profile.radius_m;
  for (const StrokeSegment& ss : stroke.segments) {
    // Smallest radius of the curvature points on the segment and of those nearest its ends.
    double radius = std::min(radius_near(positions, radii, ss.start_m),
                             radius_near(positions, radii, ss.end_m));
    auto it = std::lower_bound(positions.begin(), positions.end(), ss.start_m);
    for (; it != positions.end() && *it <= ss.end_m; ++it) {
      radius = std::min(radius, radii[static_cast<std::size_t>(it - positions.begin())]);
    }
    Segment& s = graph.segments[ss.segment];
    s.radius_m = radius;
    s.curvature_level = curvature_level(
        radius,
        is_junction(graph, graph.from_node_id(s)) || is_junction(graph, graph.to_node_id(s)), p);
    if (radius < p.sharp_bend_radius_m) s.reasons.add("SHARP_BEND");
  }
}

}  // namespace

void assign_curvature_costs(RoadGraph& graph, const Stroke& stroke, const GeometryParameters& p) {
  std::vector<double> weights;
  weights.reserve(stroke.segments.size());
  for (const StrokeSegment& s : stroke.segments) {
    const int level = *graph.segments[s.segment].curvature_level;
    weights.push_back(p.level_weight[static_cast<std::size_t>(level)]);
  }
  const std::vector<double> mean =
      windowed_mean(stroke, weights, p.window_half_length_m, p.own_segment_weight);
  for (std::size_t i = 0; i < stroke.segments.size(); ++i) {
    // The epsilon keeps an exact quotient (3.0 from uniform weights) from flooring to 2.
    const double cost = std::isnan(mean[i]) ? 0.0 : std::floor(mean[i] + 1e-9);
    graph.segments[stroke.segments[i].segment].curvature_cost =
        static_cast<int>(std::clamp(cost, 0.0, 14.0));
  }
}

void compute_geometry_costs(RoadGraph& graph, const GeometryParameters& p) {
  for (RoadPiece& piece : graph.pieces) piece.class_cost = class_cost(piece.highway, p);
  for (Segment& s : graph.segments) {
    const std::string_view highway = graph.highway(s);
    const std::string_view base = highway.substr(0, highway.find("_link"));
    if (base == "motorway" || base == "trunk") s.reasons.add("NOT_CROSSABLE_CLASS");
    if (s.tunnel) s.reasons.add("TUNNEL");
  }
  assign_junction_distances(graph, p);
  for_each_stroke(graph, [&](const Stroke& stroke) {
    assign_radii(graph, stroke, p);
    assign_curvature_costs(graph, stroke, p);
  });
}

}  // namespace roadcross::preprocess
