// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "map_impl.hpp"

namespace roadcross {
namespace detail {

namespace {
// Columns read by assess, in this order (see schema/src/schema.cpp for meanings and units):
// the segment's identity (as nearest() reads it), then its cost terms.
constexpr const char* kAssessColumns =
    "osm_way_id, highway, name, length_m, class_cost, junction_distance_m, radius_m, "
    "curvature_level, curvature_cost, elevation_cost, "
    "landform, maxspeed_kmh, lanes, width_m, context_score, crossing_distance_m, rank, score, "
    "reasons, tunnel, override_note, override_no_crossing, override_force_suitable";
// Schema version 2 added these; a version 1 DB reads NULLs in their place.
constexpr const char* kSightColumns =
    ", sight_forward_m, sight_backward_m, sight_min_m, required_sight_m";
constexpr const char* kNoSightColumns = ", NULL, NULL, NULL, NULL";
// Schema version 3 added these; older DBs read NULLs (unknown) in their place.
constexpr const char* kKerbColumns =
    ", kerb, kerb_height_m, crossing_island, sidewalk_left, sidewalk_right";
constexpr const char* kNoKerbColumns = ", NULL, NULL, NULL, NULL, NULL";
}  // namespace

Queries::Queries(sqlite::Database& db, bool has_sight, bool has_kerbs)
    : candidates(db.prepare("SELECT s.fid, s.geom FROM " + std::string(schema::kSegmentsRtree) +
                            " r JOIN " + std::string(schema::kSegmentsTable) +
                            " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                            "r.maxy >= ?3 AND r.miny <= ?4")),
      attributes(db.prepare("SELECT osm_way_id, highway, name, length_m FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      assessment(db.prepare(std::string("SELECT ") + kAssessColumns +
                            (has_sight ? kSightColumns : kNoSightColumns) +
                            (has_kerbs ? kKerbColumns : kNoKerbColumns) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      rtree_holder(
          db.prepare("SELECT id FROM " + std::string(schema::kSegmentsRtree) + " LIMIT 1")),
      segments_at(db.prepare("SELECT s.fid, s.from_node_id, s.to_node_id, s.geom FROM " +
                             std::string(schema::kSegmentsRtree) + " r JOIN " +
                             std::string(schema::kSegmentsTable) +
                             " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                             "r.maxy >= ?3 AND r.miny <= ?4")) {
  rtree_holder.step();
}

Thresholds thresholds_from(const MapInfo& info) {
  Thresholds t;
  for (const auto& [key, value] : info.metadata) {
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (end == value.c_str()) continue;
    if (key == "param.suitability.valid_distance_m") t.valid_distance_m = number;
    if (key == "param.suitability.threshold") t.threshold = number;
    if (key == "param.sight.limited_visibility_unsuitable")
      t.limited_visibility_unsuitable = number != 0.0;
    if (key == "param.suitability.max_kerb_height_m") t.max_kerb_height_m = number;
  }
  return t;
}

}  // namespace detail

const char* describe_reason(const std::string& code) noexcept {
  if (code == "TOO_FAR_FROM_ROAD") return "too far from the road centreline to be at the kerb";
  if (code == "NEAR_JUNCTION")
    return "close to a junction, where traffic turns in from several sides";
  if (code == "SHARP_BEND") return "the road bends sharply here: approaching cars are seen late";
  if (code == "CREST_OR_DIP") return "a crest or dip hides approaching cars";
  if (code == "BUSY_ROAD") return "a fast, wide or busy road";
  if (code == "NOT_CROSSABLE_CLASS") return "a motorway or trunk road: never crossed on foot";
  if (code == "TUNNEL") return "in a tunnel or under a cover";
  if (code == "NO_ELEVATION") return "no elevation data here: crests and dips are unknown";
  if (code == "LOW_SCORE") return "score + context score is below the suitability threshold";
  if (code == "OVERRIDE") return "an operator override applies";
  if (code == "LIMITED_VISIBILITY")
    return "the view along the road is shorter than a crossing needs";
  if (code == "KERB_TOO_HIGH") return "a kerb here is higher than the robot can climb";
  if (code == "NO_PAVEMENT_FAR_SIDE")
    return "the far side of the road is tagged without a pavement to cross onto";
  return "see docs/cost-model.md";
}

namespace {

std::optional<int> optional_int(const sqlite::Statement& row, int i) {
  if (row.column_is_null(i)) return std::nullopt;
  return static_cast<int>(row.column_int64(i));
}

std::optional<double> optional_double(const sqlite::Statement& row, int i) {
  if (row.column_is_null(i)) return std::nullopt;
  return row.column_double(i);
}

std::optional<bool> optional_flag(const sqlite::Statement& row, int i) {
  if (row.column_is_null(i)) return std::nullopt;
  return row.column_int64(i) != 0;
}

/// Appends the comma-separated codes of `text` to `out`, with room for `extra` more.
void split_codes(std::string_view text, std::vector<std::string>& out, std::size_t extra) {
  out.reserve(static_cast<std::size_t>(std::count(text.begin(), text.end(), ',')) + 1 + extra);
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string_view::npos) end = text.size();
    if (end > start) out.emplace_back(text.substr(start, end - start));
    start = end + 1;
  }
}

bool has(const std::vector<std::string>& codes, std::string_view code) {
  return std::find(codes.begin(), codes.end(), code) != codes.end();
}

}  // namespace

namespace {

// Reads the segment's identity and cost terms (one primary-key read of the `assessment`
// statement) into `a` and applies the suitability rule. a.road.segment_id, a.road.distance_m,
// a.robot_side, a.max_kerb_height_m and the thresholds must be set. The one place the rule
// lives: assess and assess_segment both judge through it, so that a map view can never
// disagree with assess.
Status judge(sqlite::Statement& row, Assessment& a, bool limited_visibility_unsuitable) {
  row.bind(1, a.road.segment_id);
  if (!row.step()) {
    row.reset();
    return Status{StatusCode::not_found,
                  "no segment with fid " + std::to_string(a.road.segment_id)};
  }
  a.road.osm_way_id = row.column_int64(0);
  a.road.highway = row.column_text_view(1);
  a.road.name = row.column_text_view(2);
  a.road.segment_length_m = row.column_double(3);
  a.class_cost = optional_int(row, 4);
  a.junction_distance_m = optional_double(row, 5);
  a.radius_m = optional_double(row, 6);
  a.curvature_level = optional_int(row, 7);
  a.curvature_cost = optional_int(row, 8);
  a.elevation_cost = optional_int(row, 9);
  if (!row.column_is_null(10)) a.landform.emplace(row.column_text_view(10));
  a.maxspeed_kmh = optional_double(row, 11);
  a.lanes = optional_int(row, 12);
  a.width_m = optional_double(row, 13);
  a.context_score = optional_int(row, 14);
  a.crossing_distance_m = optional_double(row, 15);
  a.rank = optional_int(row, 16);
  a.score = optional_int(row, 17);
  // Room for the codes added below (TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE,
  // KERB_TOO_HIGH, NO_PAVEMENT_FAR_SIDE).
  split_codes(row.column_text_view(18), a.reasons, 6);
  a.tunnel = row.column_int64(19) != 0;
  a.override_note = row.column_text_view(20);
  const bool no_crossing = row.column_int64(21) != 0;
  const bool force_suitable = row.column_int64(22) != 0;
  a.sight_forward_m = optional_double(row, 23);
  a.sight_backward_m = optional_double(row, 24);
  a.sight_min_m = optional_double(row, 25);
  a.required_sight_m = optional_double(row, 26);
  if (!row.column_is_null(27)) a.kerb.emplace(row.column_text_view(27));
  a.kerb_height_m = optional_double(row, 28);
  a.crossing_island = optional_flag(row, 29);
  a.sidewalk_left = optional_flag(row, 30);
  a.sidewalk_right = optional_flag(row, 31);
  row.reset();

  a.valid = a.road.distance_m <= a.valid_distance_m;
  if (!a.valid) a.reasons.insert(a.reasons.begin(), "TOO_FAR_FROM_ROAD");
  if (!a.elevation_cost && !has(a.reasons, "NO_ELEVATION")) a.reasons.emplace_back("NO_ELEVATION");
  const int total = a.score.value_or(0) + a.context_score.value_or(0);
  // What the robot cannot do: climb a kerb known to be higher than it can, or leave the road
  // onto a far side tagged without a pavement. Unknown (NULL) never forbids.
  const bool kerb_too_high = a.kerb_height_m && *a.kerb_height_m > a.max_kerb_height_m + 1e-9;
  if (kerb_too_high) a.reasons.emplace_back("KERB_TOO_HIGH");
  if (a.robot_side != 0)
    a.pavement_far_side = a.robot_side > 0 ? a.sidewalk_right : a.sidewalk_left;
  const bool stranded = a.pavement_far_side.has_value() && !*a.pavement_far_side;
  if (stranded) a.reasons.emplace_back("NO_PAVEMENT_FAR_SIDE");
  const bool forbidden =
      has(a.reasons, "NOT_CROSSABLE_CLASS") || a.tunnel || no_crossing || kerb_too_high || stranded;
  const bool hidden = limited_visibility_unsuitable && has(a.reasons, "LIMITED_VISIBILITY");
  const bool good_enough = a.score.has_value() && total >= a.threshold;
  if (!good_enough && !force_suitable) a.reasons.emplace_back("LOW_SCORE");
  if ((no_crossing || force_suitable) && !has(a.reasons, "OVERRIDE"))
    a.reasons.emplace_back("OVERRIDE");
  // An operator's force_suitable overrides the score and the computed sight distance (the
  // operator may know of a mirror, or of a hedge cut back), never the class, a tunnel,
  // validity, or what the robot cannot climb or reach.
  a.suitable = a.valid && !forbidden && ((good_enough && !hidden) || force_suitable);
  return Status{};
}

}  // namespace

namespace {
Status check_kerb_option(const AssessOptions& options) {
  if (options.max_kerb_height_m &&
      !(*options.max_kerb_height_m >= 0.0 && std::isfinite(*options.max_kerb_height_m))) {
    return Status{StatusCode::invalid_argument, "max_kerb_height_m must be a finite number >= 0"};
  }
  return Status{};
}
}  // namespace

Result<Assessment> Map::assess(const Position& position, const AssessOptions& options) noexcept {
  if (!(options.max_distance_m > 0.0)) {
    return Result<Assessment>{Status{StatusCode::invalid_argument, "max_distance_m must be > 0"},
                              std::nullopt};
  }
  if (Status s = check_kerb_option(options); !s.ok()) {
    return Result<Assessment>{std::move(s), std::nullopt};
  }
  Impl& impl = *impl_;
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    Status status = impl.locate(position, options.max_distance_m, a.road);
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
    a.max_kerb_height_m = options.max_kerb_height_m.value_or(impl.thresholds.max_kerb_height_m);
    a.robot_side = impl.side_of(a.road);
    status = judge(impl.queries.assessment, a, impl.thresholds.limited_visibility_unsuitable);
    if (status.code == StatusCode::not_found) {
      status = Status{StatusCode::corrupt_database, impl.info.path + ": segment without a row"};
    }
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    return result;
  } catch (const std::exception& e) {
    impl.queries.candidates.reset();
    impl.queries.assessment.reset();
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl.info.path + ": " + e.what()}, std::nullopt};
  }
}

Result<Assessment> Map::assess_segment(std::int64_t segment_id,
                                       const AssessOptions& options) noexcept {
  if (Status s = check_kerb_option(options); !s.ok()) {
    return Result<Assessment>{std::move(s), std::nullopt};
  }
  Impl& impl = *impl_;
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
    a.max_kerb_height_m = options.max_kerb_height_m.value_or(impl.thresholds.max_kerb_height_m);
    a.road.segment_id = segment_id;
    a.road.distance_m = 0.0;  // standing on the centreline: the side is unknown
    Status status =
        judge(impl.queries.assessment, a, impl.thresholds.limited_visibility_unsuitable);
    if (!status.ok()) {
      status.message = impl.info.path + ": " + status.message;
      return Result<Assessment>{std::move(status), std::nullopt};
    }
    return result;
  } catch (const std::exception& e) {
    impl.queries.assessment.reset();
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl.info.path + ": " + e.what()}, std::nullopt};
  }
}

}  // namespace roadcross
