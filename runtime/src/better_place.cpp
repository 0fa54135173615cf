// Map::better_place: a Dijkstra walk along the road graph from the robot's position, over the
// segments the R*Tree finds within the search radius, judging every segment reached.
#include <algorithm>
#include <cmath>
#include <queue>
#include <unordered_map>

#include "map_impl.hpp"
#include "polyline.hpp"
#include "roadcross/schema/verdict.hpp"

namespace roadcross {
namespace {

struct LocalSegment {
  std::int64_t id = 0, from = 0, to = 0;
  double length_m = 0.0;
  std::vector<schema::PlanePoint> points;
  std::optional<int> score, context;
  std::string reasons;
  bool tunnel = false, no_crossing = false, force_suitable = false;
  std::optional<double> crossing_distance_m;
  std::optional<double> kerb_height_m;
  std::optional<bool> sidewalk_left, sidewalk_right;
};

/// Every segment whose box meets the square of half-size `radius_m` around `p`.
std::vector<LocalSegment> load_neighbourhood(sqlite::Database& db, int schema_version,
                                             schema::PlanePoint p, double radius_m) {
  // Prepared per call: better_place is a planning query (ms), not the hot assess path.
  using C = schema::SegmentColumn;
  static const schema::SegmentSelection kColumns(
      {C::from_node_id, C::to_node_id, C::length_m, C::score, C::context_score, C::reasons,
       C::tunnel, C::override_no_crossing, C::override_force_suitable, C::crossing_distance_m,
       C::kerb_height_m, C::sidewalk_left, C::sidewalk_right},
      2);
  sqlite::Statement query = db.prepare(
      "SELECT s.fid, s.geom, " + kColumns.sql("s", schema_version) +
      ", r.minx, r.maxx, r.miny, r.maxy FROM " + std::string(schema::kSegmentsRtree) + " r JOIN " +
      std::string(schema::kSegmentsTable) +
      " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND r.maxy >= ?3 AND r.miny <= ?4");
  query.bind(1, p.x - radius_m);
  query.bind(2, p.x + radius_m);
  query.bind(3, p.y - radius_m);
  query.bind(4, p.y + radius_m);
  std::vector<LocalSegment> out;
  while (query.step()) {
    LocalSegment s;
    s.id = query.column_int64(0);
    s.from = query.column_int64(kColumns[C::from_node_id]);
    s.to = query.column_int64(kColumns[C::to_node_id]);
    s.length_m = query.column_double(kColumns[C::length_m]);
    // The walk below is a Dijkstra search: a negative length would make it loop for ever.
    if (!(std::isfinite(s.length_m) && s.length_m >= 0.0)) {
      throw detail::corrupt_segment_error(
          detail::segment_problem(s.id, "length_m must be a finite number >= 0"));
    }
    if (!schema::decode_linestring(query.column_blob(1), s.points)) {
      throw detail::corrupt_segment_error(detail::segment_problem(s.id, "malformed geometry"));
    }
    const int box = kColumns[C::sidewalk_right] + 1;  // r.minx: after the last selected column
    detail::check_in_box(s.id, s.points, query.column_double(box), query.column_double(box + 1),
                         query.column_double(box + 2), query.column_double(box + 3));
    const std::int64_t score = query.column_int64(kColumns[C::score]);
    const std::int64_t context = query.column_int64(kColumns[C::context_score]);
    // The ranges assess checks (score 1..15, |context| <= 1e6): their sum fits an int.
    const bool has_score = !query.column_is_null(kColumns[C::score]);
    if ((has_score && (score < 1 || score > 15)) || context < -1000000 || context > 1000000) {
      throw detail::corrupt_segment_error(
          detail::segment_problem(s.id, "score or context_score out of range"));
    }
    if (has_score) s.score = static_cast<int>(score);
    if (!query.column_is_null(kColumns[C::context_score])) s.context = static_cast<int>(context);
    s.reasons = detail::valid_utf8(query.column_text_view(kColumns[C::reasons]));
    s.tunnel = query.column_int64(kColumns[C::tunnel]) != 0;
    s.no_crossing = query.column_int64(kColumns[C::override_no_crossing]) != 0;
    s.force_suitable = query.column_int64(kColumns[C::override_force_suitable]) != 0;
    if (!query.column_is_null(kColumns[C::crossing_distance_m]))
      s.crossing_distance_m = query.column_double(kColumns[C::crossing_distance_m]);
    if (!query.column_is_null(kColumns[C::kerb_height_m]))
      s.kerb_height_m = query.column_double(kColumns[C::kerb_height_m]);
    if (!query.column_is_null(kColumns[C::sidewalk_left]))
      s.sidewalk_left = query.column_int64(kColumns[C::sidewalk_left]) != 0;
    if (!query.column_is_null(kColumns[C::sidewalk_right]))
      s.sidewalk_right = query.column_int64(kColumns[C::sidewalk_right]) != 0;
    out.push_back(std::move(s));
  }
  return out;
}

/// The point at `fraction` along a polyline and the direction there.
std::pair<schema::PlanePoint, double> point_and_direction(
    const std::vector<schema::PlanePoint>& pts, double fraction) {
  double total = 0.0;
  for (std::size_t i = 1; i < pts.size(); ++i)
    total += std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y);
  double target = fraction * total;
  for (std::size_t i = 1; i < pts.size(); ++i) {
    const double dx = pts[i].x - pts[i - 1].x, dy = pts[i].y - pts[i - 1].y,
                 edge = std::hypot(dx, dy);
    if (target <= edge || i + 1 == pts.size()) {
      const double t = edge > 0.0 ? std::clamp(target / edge, 0.0, 1.0) : 0.0;
      return {{pts[i - 1].x + t * dx, pts[i - 1].y + t * dy}, std::atan2(dy, dx)};
    }
    target -= edge;
  }
  return {pts.front(), 0.0};
}

/// Direction of walking out of segment `s` at its start (forward) or end (backward).
double departure_yaw(const LocalSegment& s, bool forward) {
  const auto& p = s.points;
  if (forward) return std::atan2(p[1].y - p[0].y, p[1].x - p[0].x);
  const std::size_t n = p.size();
  return std::atan2(p[n - 2].y - p[n - 1].y, p[n - 2].x - p[n - 1].x);
}

/// Direction of walking when arriving at the far end of segment `s`.
double arrival_yaw(const LocalSegment& s, bool forward) {
  return geo::normalize_angle_rad(departure_yaw(s, !forward) + geo::kPi);
}

struct Reached {
  double distance_m;  // walking distance to the segment's midpoint
  bool forward;       // walked in the segment's own direction
};

}  // namespace

Result<BetterPlaces> Map::better_place(const Position& position,
                                       const BetterPlaceOptions& options) noexcept {
  if (!(options.search_radius_m > 0.0 && options.search_radius_m <= detail::kMaxWalkingRadiusM)) {
    return Result<BetterPlaces>{
        Status{StatusCode::invalid_argument, "search_radius_m must be in (0, 10000] metres"},
        std::nullopt};
  }
  Result<Assessment> here = assess(position, options.assess);
  if (!here.ok()) return Result<BetterPlaces>{here.status, std::nullopt};
  impl_->budget->restart();
  // The candidates are judged with the robot's uncertainty turned into the grid at its fix
  // (the convergence hardly changes over a walk of search_radius_m).
  PositionUncertainty grid_uncertainty;
  if (position.uncertainty) {
    grid_uncertainty = *position.uncertainty;
    if (grid_uncertainty.frame == PositionUncertainty::Frame::enu) {
      try {
        Status converted = detail::uncertainty_in_grid(
            *position.uncertainty, impl_->info.zone,
            {here->road.query.easting_m, here->road.query.northing_m}, grid_uncertainty);
        if (!converted.ok()) return Result<BetterPlaces>{converted, std::nullopt};
      } catch (const std::exception& e) {
        return Result<BetterPlaces>{Status{StatusCode::invalid_argument, e.what()}, std::nullopt};
      }
    }
  }
  try {
    const schema::PlanePoint robot{here->road.query.easting_m, here->road.query.northing_m};
    // The walk starts where the robot reaches its road: every segment it can reach within
    // search_radius_m lies that close to this point, whatever the robot's distance from it.
    const schema::PlanePoint on_road{here->road.closest.easting_m, here->road.closest.northing_m};
    std::vector<LocalSegment> local = load_neighbourhood(impl_->db, impl_->info.schema_version,
                                                         on_road, options.search_radius_m + 20.0);
    std::unordered_map<std::int64_t, std::vector<std::size_t>> at_node;
    std::size_t start = local.size();
    for (std::size_t i = 0; i < local.size(); ++i) {
      at_node[local[i].from].push_back(i);
      at_node[local[i].to].push_back(i);
      if (local[i].id == here->road.segment_id) start = i;
    }
    if (start == local.size()) {
      return Result<BetterPlaces>{Status{StatusCode::corrupt_database, "own segment not indexed"},
                                  std::nullopt};
    }
    // The robot's side: left (+1) or right (-1) of its segment's direction, and its offset.
    const detail::PolylineProjection on = detail::project_onto_polyline(local[start].points, robot);
    const double yaw = detail::polyline_direction_rad(local[start].points, on);
    const double cross =
        std::cos(yaw) * (robot.y - on.closest.y) - std::sin(yaw) * (robot.x - on.closest.x);
    const double side_of_start = cross >= 0.0 ? 1.0 : -1.0;
    // Candidates stand at the robot's offset from the centreline, but never farther than the
    // valid distance: a place offered as suitable must be one assess calls suitable.
    const double valid_distance_m =
        options.assess.valid_distance_m.value_or(impl_->thresholds.valid_distance_m);
    const double offset_m = std::min(std::max(here->road.distance_m, 1.0), valid_distance_m);
    double along_m = 0.0;
    for (std::size_t i = 0; i < on.edge_index; ++i) {
      along_m += std::hypot(local[start].points[i + 1].x - local[start].points[i].x,
                            local[start].points[i + 1].y - local[start].points[i].y);
    }
    along_m +=
        on.edge_fraction *
        std::hypot(local[start].points[on.edge_index + 1].x - local[start].points[on.edge_index].x,
                   local[start].points[on.edge_index + 1].y - local[start].points[on.edge_index].y);

    // Dijkstra over graph nodes; the side relative to the walking direction is kept.
    using Entry = std::pair<double, std::int64_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    std::unordered_map<std::int64_t, double> node_distance;
    std::unordered_map<std::size_t, Reached> reached;
    const double length = local[start].length_m;
    reached[start] = {std::abs(along_m - 0.5 * length), true};
    node_distance[local[start].from] = along_m;
    node_distance[local[start].to] = length - along_m;
    queue.push({along_m, local[start].from});
    queue.push({length - along_m, local[start].to});
    // Walking from the start towards its from-node is walking backwards: the robot's side
    // relative to the walking direction flips. Track, per node, the side relative to walking.
    std::unordered_map<std::int64_t, double> side_at_node{{local[start].from, -side_of_start},
                                                          {local[start].to, side_of_start}};
    std::unordered_map<std::size_t, double> side_of_segment{{start, side_of_start}};
    // At a junction the walk goes straight on, or turns into a side road on the robot's own
    // side; a side road across the road could only be reached by crossing, which is what the
    // robot is looking for a place to do. Per node: the segment the walk arrived by and its
    // direction there.
    std::unordered_map<std::int64_t, std::pair<std::size_t, double>> arrived{
        {local[start].from, {start, arrival_yaw(local[start], false)}},
        {local[start].to, {start, arrival_yaw(local[start], true)}}};
    while (!queue.empty()) {
      const auto [d, node] = queue.top();
      queue.pop();
      if (d > node_distance[node] || d > options.search_radius_m) continue;
      const auto [came_by, heading] = arrived[node];
      std::vector<std::size_t> onward;
      for (std::size_t i : at_node[node]) {
        if (i != came_by) onward.push_back(i);
      }
      if (onward.size() > 1) {
        // Straight on is always allowed; a turn only towards the robot's own side (a side road
        // on the other side would have to be reached by crossing).
        // (copies: clang 14 cannot capture structured bindings)
        const auto turn = [&, node = node, heading = heading](std::size_t i) {
          return geo::angle_difference_rad(departure_yaw(local[i], local[i].from == node), heading);
        };
        const std::size_t straightest = *std::min_element(
            onward.begin(), onward.end(),
            [&](std::size_t a, std::size_t b) { return std::abs(turn(a)) < std::abs(turn(b)); });
        constexpr double kClearTurnRad = 0.3;
        const double own_side = side_at_node[node];  // +1 left of the walking direction
        std::erase_if(onward, [&](std::size_t i) {
          return i != straightest && !(own_side * turn(i) > kClearTurnRad);
        });
      }
      for (std::size_t i : onward) {
        if (i == start) continue;
        const bool forward = local[i].from == node;
        const double mid = d + 0.5 * local[i].length_m;
        auto it = reached.find(i);
        if (it == reached.end() || mid < it->second.distance_m) {
          reached[i] = {mid, forward};
          side_of_segment[i] = forward ? side_at_node[node] : -side_at_node[node];
        }
        const std::int64_t next = forward ? local[i].to : local[i].from;
        const double next_d = d + local[i].length_m;
        auto nd = node_distance.find(next);
        if (nd == node_distance.end() || next_d < nd->second) {
          node_distance[next] = next_d;
          side_at_node[next] = side_at_node[node];
          arrived[next] = {i, arrival_yaw(local[i], forward)};
          queue.push({next_d, next});
        }
      }
    }

    BetterPlaces result;
    const schema::VerdictThresholds thresholds{
        options.assess.threshold.value_or(impl_->thresholds.threshold),
        impl_->thresholds.limited_visibility_unsuitable};
    const double max_kerb_height_m = here->max_kerb_height_m;
    for (const auto& [i, r] : reached) {
      if (r.distance_m > options.search_radius_m) continue;
      const LocalSegment& s = local[i];
      const schema::Verdict verdict = schema::judge_segment(
          {s.score, s.context, s.reasons, s.tunnel, s.no_crossing, s.force_suitable}, thresholds);
      // Never-crossable places and junctions are not offered at all.
      if (verdict.not_crossable_class || verdict.tunnel || verdict.no_crossing ||
          schema::has_reason(s.reasons, "NEAR_JUNCTION"))
        continue;
      Candidate c;
      c.segment_id = s.id;
      c.walking_distance_m = r.distance_m;
      c.score = s.score.value_or(0) + s.context.value_or(0);
      c.designated_crossing = s.crossing_distance_m && *s.crossing_distance_m <= 5.0;
      const auto [mid, direction] = point_and_direction(s.points, 0.5);
      const double side = side_of_segment[i];
      // The same two robot rules as assess: a kerb known to be too high, a far side (the one
      // across from the side the robot walks on) tagged without a pavement.
      const bool kerb_too_high = s.kerb_height_m && *s.kerb_height_m > max_kerb_height_m + 1e-9;
      const std::optional<bool> far_pavement = side > 0 ? s.sidewalk_right : s.sidewalk_left;
      const bool stranded = far_pavement.has_value() && !*far_pavement;
      // At offset_m, within the valid distance: the segment's verdict and the robot's rules.
      c.suitable = verdict.suitable && !kerb_too_high && !stranded;
      c.point = {mid.x - side * offset_m * std::sin(direction),
                 mid.y + side * offset_m * std::cos(direction)};
      // From the left (+1) of the road's direction the crossing points to its right, and back.
      c.crossing_heading_rad = geo::normalize_angle_rad(direction - side * geo::kPi / 2.0);
      std::size_t start_code = 0;
      while (start_code < s.reasons.size()) {
        std::size_t end = s.reasons.find(',', start_code);
        if (end == std::string::npos) end = s.reasons.size();
        if (end > start_code) c.reasons.push_back(s.reasons.substr(start_code, end - start_code));
        start_code = end + 1;
      }
      if (kerb_too_high) c.reasons.emplace_back("KERB_TOO_HIGH");
      if (stranded) c.reasons.emplace_back("NO_PAVEMENT_FAR_SIDE");
      result.candidates.push_back(std::move(c));
    }
    if (position.uncertainty) {
      // A better place must stay suitable when the robot stands there with the same
      // uncertainty: judge each suitable candidate over its own region.
      for (Candidate& c : result.candidates) {
        if (!c.suitable) continue;
        Result<Assessment> there = assess(
            Position::utm(c.point.easting_m, c.point.northing_m).with_uncertainty(grid_uncertainty),
            options.assess);
        if (!there.ok()) return Result<BetterPlaces>{there.status, std::nullopt};
        c.suitable = there->suitable;
        c.suitable_share = there->region->suitable_share;
        for (const char* code : {"POSITION_UNCERTAIN", "AMBIGUOUS_ROAD"}) {
          if (std::find(there->reasons.begin(), there->reasons.end(), code) != there->reasons.end())
            c.reasons.emplace_back(code);
        }
      }
    }
    std::sort(result.candidates.begin(), result.candidates.end(),
              [](const Candidate& a, const Candidate& b) {
                if (a.suitable != b.suitable) return a.suitable;
                if (a.designated_crossing != b.designated_crossing) return a.designated_crossing;
                if (a.score != b.score) return a.score > b.score;
                if (a.walking_distance_m != b.walking_distance_m)
                  return a.walking_distance_m < b.walking_distance_m;
                return a.segment_id < b.segment_id;
              });
    if (result.candidates.size() > options.max_candidates)
      result.candidates.resize(options.max_candidates);
    if (result.candidates.empty() || !result.candidates.front().suitable) {
      result.candidates.erase(std::remove_if(result.candidates.begin(), result.candidates.end(),
                                             [](const Candidate& c) { return !c.suitable; }),
                              result.candidates.end());
      result.reason = "no suitable place within " +
                      std::to_string(static_cast<int>(options.search_radius_m)) +
                      " m of walking along the road";
    }
    return Result<BetterPlaces>{Status{}, std::move(result)};
  } catch (const std::exception& e) {
    return Result<BetterPlaces>{detail::status_of(e, impl_->info.path), std::nullopt};
  }
}

}  // namespace roadcross
