#include "roadcross/preprocess/geometry/geometry_cost.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <optional>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/geometry/curvature.hpp"
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
  out.push_back({s, "junction_extent_m", &junction_extent_m, 0, 1000, false,
                 "curvature level 5 on every segment that comes closer to a junction along the "
                 "road, metres (the method's first piece next to a junction: <= 20)"});
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
  out.push_back({s, "window_through_junctions", &window_through_junctions, 0, 1, true,
                 "1: the curvature window goes on through a junction along the road (same way, "
                 "else same name or ref), never into a side road; 0: it ends at every junction"});
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

/// Sets junction_distance_m and NEAR_JUNCTION; returns, per segment, 1 where the segment comes
/// closer than junction_extent_m to a junction along the road (or touches one): its curvature
/// level is 5.
std::vector<std::uint8_t> assign_junction_distances(RoadGraph& graph, const Incidences& nodes,
                                                    const GeometryParameters& p) {
  const std::vector<double> distance = distance_to_junction(graph, nodes);
  const auto at = [&](std::int64_t node) { return distance[nodes.index_of(node)]; };
  std::vector<std::uint8_t> within_extent(graph.segments.size(), 0);
  for (const RoadPiece& piece : graph.pieces) {
    const double from_end = at(piece.from_node_id), to_end = at(piece.to_node_id);
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      Segment& s = graph.segments[piece.first_segment + k];
      const double start = graph.offset_in_piece_m(s), length = graph.length_m(s);
      // Measured from the segment's midpoint: where a robot crossing "at this segment" stands.
      const double mid = start + 0.5 * length;
      const double d = std::min(mid + from_end, piece.length_m - mid + to_end);
      if (std::isfinite(d)) {
        s.junction_distance_m = d;
        if (d < p.near_junction_m) s.reasons.add("NEAR_JUNCTION");
      }
      // The level, though, from the segment's nearer end: the junction's stretch of road is
      // level 5 over the same length whatever the segment length.
      const double nearer_end =
          std::min(start + from_end, piece.length_m - (start + length) + to_end);
      within_extent[piece.first_segment + k] =
          nearer_end <= 0.0 || nearer_end < p.junction_extent_m ? 1 : 0;
    }
  }
  return within_extent;
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

void assign_radii(RoadGraph& graph, const Stroke& stroke,
                  const std::vector<std::uint8_t>& within_junction_extent,
                  const GeometryParameters& p) {
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
    s.curvature_level = curvature_level(radius, within_junction_extent[ss.segment] != 0, p);
    if (radius < p.sharp_bend_radius_m) s.reasons.add("SHARP_BEND");
  }
}

/// Direction (radians) of walking along `piece` away from the node at its from-end
/// (`from_to_end` false) or its to-end (true), from the piece's first edge there.
double departure_direction_rad(const RoadPiece& piece, bool from_to_end) {
  const std::vector<PlanePoint>& pts = piece.points;
  const PlanePoint a = from_to_end ? pts[pts.size() - 1] : pts[0];
  const PlanePoint b = from_to_end ? pts[pts.size() - 2] : pts[1];
  return std::atan2(b.y - a.y, b.x - a.x);
}

/// |turn| from walking direction `heading_rad` onto direction `onto_rad`, radians 0..pi.
double turn_rad(double heading_rad, double onto_rad) {
  const double d = geo::remainder_fast(onto_rad - heading_rad, 2.0 * std::acos(-1.0));
  return std::abs(d);
}

/// The piece end at graph node `node` the road goes on by, after arriving there along `arrived`
/// (the piece end at `node` the walk came in by), or none: the same way if it passes through
/// (the straightest such end if several), else the straightest end of a piece of the same name
/// or ref. A side road is never taken; a road that ends at the junction ends there.
std::optional<Incidence> road_goes_on(const RoadGraph& graph, const Incidences& nodes,
                                      std::int64_t node, Incidence arrived) {
  const std::span<const Incidence> ends = nodes.at(node);
  if (ends.size() < 3) return std::nullopt;  // a dead end (a degree-2 node is no stroke end)
  const RoadPiece& in = graph.pieces[arrived.piece];
  // Walking direction on arrival: the reverse of leaving the node along the arrival piece.
  const double heading = departure_direction_rad(in, arrived.at_end) + std::acos(-1.0);
  const auto best_of = [&](auto&& same_road) -> std::optional<Incidence> {
    std::optional<Incidence> best;
    double best_turn = 0.0;
    for (const Incidence& end : ends) {
      if (end.piece == arrived.piece && end.at_end == arrived.at_end) continue;
      if (!same_road(graph.pieces[end.piece])) continue;
      const double t =
          turn_rad(heading, departure_direction_rad(graph.pieces[end.piece], end.at_end));
      if (!best || t < best_turn) {
        best = end;
        best_turn = t;
      }
    }
    return best;
  };
  if (auto same_way = best_of([&](const RoadPiece& q) { return q.osm_way_id == in.osm_way_id; }))
    return same_way;
  return best_of([&](const RoadPiece& q) {
    return (!in.name.empty() && q.name == in.name.view()) ||
           (!in.ref.empty() && q.ref == in.ref.view());
  });
}

/// The segments of the road beyond one end of `stroke`, within `reach_m` of it, following the
/// road through junctions (road_goes_on) and degree-2 joints. Positions are the distance from
/// the stroke's end, [start, end) increasing away from it. Pieces in `used` are not entered
/// again (the stroke's own, and those already walked: a ring is not counted twice).
std::vector<StrokeSegment> road_beyond(const RoadGraph& graph, const Incidences& nodes,
                                       std::int64_t node, Incidence arrived, double reach_m,
                                       std::vector<std::size_t>& used) {
  std::vector<StrokeSegment> out;
  double walked_m = 0.0;
  while (walked_m < reach_m) {
    std::optional<Incidence> next;
    const std::span<const Incidence> ends = nodes.at(node);
    if (ends.size() == 2) {
      next =
          (ends[0].piece == arrived.piece && ends[0].at_end == arrived.at_end) ? ends[1] : ends[0];
    } else {
      next = road_goes_on(graph, nodes, node, arrived);
    }
    if (!next || std::find(used.begin(), used.end(), next->piece) != used.end()) break;
    used.push_back(next->piece);
    const RoadPiece& piece = graph.pieces[next->piece];
    const bool reversed = next->at_end;  // leaving from its to-node: walking it backwards
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      const std::size_t index = piece.first_segment + (reversed ? piece.segment_count - 1 - k : k);
      const double length = graph.length_m(graph.segments[index]);
      out.push_back({index, reversed, walked_m, walked_m + length});
      walked_m += length;
      if (walked_m >= reach_m) break;
    }
    node = reversed ? piece.from_node_id : piece.to_node_id;
    arrived = {next->piece, !reversed};
  }
  return out;
}

/// `stroke` with the road beyond both its ends (road_beyond, up to `reach_m`) added as segments
/// before and after it; `own_first` is set to the index of the stroke's first segment in it.
Stroke extend_along_road(const RoadGraph& graph, const Incidences& nodes, const Stroke& stroke,
                         double reach_m, std::size_t& own_first) {
  own_first = 0;
  if (stroke.closed || stroke.segments.empty()) return stroke;
  std::vector<std::size_t> used;
  for (const StrokeSegment& ss : stroke.segments) {
    const std::size_t piece = graph.segments[ss.segment].piece_index;
    if (used.empty() || used.back() != piece) used.push_back(piece);
  }
  // The stroke's first segment starts at its piece's from-node unless walked reversed.
  const StrokeSegment& first = stroke.segments.front();
  const Segment& first_segment = graph.segments[first.segment];
  const std::int64_t start_node =
      first.reversed ? graph.to_node_id(first_segment) : graph.from_node_id(first_segment);
  const std::vector<StrokeSegment> before = road_beyond(
      graph, nodes, start_node, {first_segment.piece_index, first.reversed}, reach_m, used);
  const StrokeSegment& last = stroke.segments.back();
  const Segment& last_segment = graph.segments[last.segment];
  const std::int64_t end_node =
      last.reversed ? graph.from_node_id(last_segment) : graph.to_node_id(last_segment);
  const std::vector<StrokeSegment> after = road_beyond(
      graph, nodes, end_node, {last_segment.piece_index, !last.reversed}, reach_m, used);

  Stroke extended;
  extended.length_m = stroke.length_m;
  extended.segments.reserve(before.size() + stroke.segments.size() + after.size());
  for (auto it = before.rbegin(); it != before.rend(); ++it) {
    extended.segments.push_back({it->segment, it->reversed, -it->end_m, -it->start_m});
  }
  own_first = extended.segments.size();
  extended.segments.insert(extended.segments.end(), stroke.segments.begin(), stroke.segments.end());
  for (const StrokeSegment& ss : after) {
    extended.segments.push_back(
        {ss.segment, ss.reversed, stroke.length_m + ss.start_m, stroke.length_m + ss.end_m});
  }
  return extended;
}

}  // namespace

void assign_curvature_costs(RoadGraph& graph, const Stroke& stroke, const GeometryParameters& p,
                            const Incidences* through_junctions) {
  std::size_t own_first = 0;
  const Stroke window_road =
      through_junctions
          ? extend_along_road(graph, *through_junctions, stroke, p.window_half_length_m, own_first)
          : stroke;
  std::vector<double> weights;
  weights.reserve(window_road.segments.size());
  for (const StrokeSegment& s : window_road.segments) {
    const int level = *graph.segments[s.segment].curvature_level;
    weights.push_back(p.level_weight[static_cast<std::size_t>(level)]);
  }
  const std::vector<double> mean =
      windowed_mean(window_road, weights, p.window_half_length_m, p.own_segment_weight);
  for (std::size_t i = 0; i < stroke.segments.size(); ++i) {
    // The epsilon keeps an exact quotient (3.0 from uniform weights) from flooring to 2.
    const double m = mean[own_first + i];
    const double cost = std::isnan(m) ? 0.0 : std::floor(m + 1e-9);
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
  const Incidences nodes(graph);
  const std::vector<std::uint8_t> within_junction_extent =
      assign_junction_distances(graph, nodes, p);
  // Every level first: a window reaches beyond its stroke into the road that goes on. A stroke
  // writes only its own segments (radius, level, reasons; then the cost from the levels), so
  // the strokes run on every core.
  for_each_stroke_parallel(graph, nodes, [&](const Stroke& stroke) {
    assign_radii(graph, stroke, within_junction_extent, p);
  });
  const Incidences* through = p.window_through_junctions != 0.0 ? &nodes : nullptr;
  for_each_stroke_parallel(graph, nodes, [&](const Stroke& stroke) {
    assign_curvature_costs(graph, stroke, p, through);
  });
}

}  // namespace roadcross::preprocess
