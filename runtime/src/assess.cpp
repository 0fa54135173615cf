// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
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
}  // namespace

Queries::Queries(sqlite::Database& db, bool has_sight)
    : candidates(db.prepare("SELECT s.fid, s.geom, r.minx, r.maxx, r.miny, r.maxy FROM " +
                            std::string(schema::kSegmentsRtree) + " r JOIN " +
                            std::string(schema::kSegmentsTable) +
                            " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                            "r.maxy >= ?3 AND r.miny <= ?4")),
      attributes(db.prepare("SELECT osm_way_id, highway, name, length_m FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      assessment(db.prepare(std::string("SELECT ") + kAssessColumns +
                            (has_sight ? kSightColumns : kNoSightColumns) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      rtree_holder(
          db.prepare("SELECT id FROM " + std::string(schema::kSegmentsRtree) + " LIMIT 1")),
      segments_at(db.prepare("SELECT s.fid, s.from_node_id, s.to_node_id, s.geom, r.minx, "
                             "r.maxx, r.miny, r.maxy FROM " +
                             std::string(schema::kSegmentsRtree) + " r JOIN " +
                             std::string(schema::kSegmentsTable) +
                             " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                             "r.maxy >= ?3 AND r.miny <= ?4")) {
  rtree_holder.step();
}

Status thresholds_from(const MapInfo& info, Thresholds& out) {
  Thresholds t;
  for (const auto& [key, value] : info.metadata) {
    double* target = key == "param.suitability.valid_distance_m" ? &t.valid_distance_m
                     : key == "param.suitability.threshold"      ? &t.threshold
                                                                 : nullptr;
    const bool visibility = key == "param.sight.limited_visibility_unsuitable";
    if (!target && !visibility) continue;
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    const bool in_range = end != value.c_str() && *end == '\0' && std::isfinite(number) &&
                          (target != &t.valid_distance_m || number >= 0.0);
    if (!in_range) {
      return {StatusCode::corrupt_database,
              info.path + ": metadata " + key + " is '" + value +
                  "', not a finite number in range. Rebuild the map with roadcross-build."};
    }
    if (target) *target = number;
    if (visibility) t.limited_visibility_unsuitable = number != 0.0;
  }
  out = t;
  return {};
}

Status check_assess_options(const AssessOptions& options) {
  if (options.valid_distance_m &&
      !(std::isfinite(*options.valid_distance_m) && *options.valid_distance_m >= 0.0)) {
    return {StatusCode::invalid_argument, "valid_distance_m must be a finite number >= 0 metres"};
  }
  if (options.threshold && !std::isfinite(*options.threshold)) {
    return {StatusCode::invalid_argument, "threshold must be a finite number"};
  }
  if (!(options.max_distance_m > 0.0 && options.max_distance_m <= kMaxSearchDistanceM)) {
    return {StatusCode::invalid_argument, "max_distance_m must be in (0, 100000] metres"};
  }
  return {};
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

// Columns of the `assessment` statement (kAssessColumns, then the sight columns).
enum AssessColumn : int {
  kOsmWayId,
  kHighway,
  kName,
  kLengthM,
  kClassCost,
  kJunctionDistanceM,
  kRadiusM,
  kCurvatureLevel,
  kCurvatureCost,
  kElevationCost,
  kLandform,
  kMaxspeedKmh,
  kLanes,
  kWidthM,
  kContextScore,
  kCrossingDistanceM,
  kRank,
  kScore,
  kReasons,
  kTunnel,
  kOverrideNote,
  kNoCrossing,
  kForceSuitable,
  kSightForwardM,
  kSightBackwardM,
  kSightMinM,
  kRequiredSightM,
};

/// Integer columns and the values roadcross-build writes (docs/cost-model.md; the flags are 0
/// or 1). context_score's bound is far beyond any parameter file's, and keeps score +
/// context_score inside int.
struct IntColumn {
  int column;
  const char* name;
  std::int64_t min, max;
  bool nullable;
};
constexpr IntColumn kIntColumns[] = {
    {kOsmWayId, "osm_way_id", INT64_MIN, INT64_MAX, false},
    {kClassCost, "class_cost", 0, 5, true},
    {kCurvatureLevel, "curvature_level", 0, 5, true},
    {kCurvatureCost, "curvature_cost", 0, 14, true},
    {kElevationCost, "elevation_cost", 0, 9, true},
    {kLanes, "lanes", 0, 1000, true},
    {kContextScore, "context_score", -1000000, 1000000, true},
    {kRank, "rank", 0, 14, true},
    {kScore, "score", 1, 15, true},
    {kTunnel, "tunnel", 0, 1, false},
    {kNoCrossing, "override_no_crossing", 0, 1, false},
    {kForceSuitable, "override_force_suitable", 0, 1, false},
};

/// Distances, speeds and widths: finite and >= 0 where present (length_m always present).
struct RealColumn {
  int column;
  const char* name;
  bool nullable;
};
constexpr RealColumn kRealColumns[] = {
    {kLengthM, "length_m", false},
    {kJunctionDistanceM, "junction_distance_m", true},
    {kRadiusM, "radius_m", true},
    {kMaxspeedKmh, "maxspeed_kmh", true},
    {kWidthM, "width_m", true},
    {kCrossingDistanceM, "crossing_distance_m", true},
    {kSightForwardM, "sight_forward_m", true},
    {kSightBackwardM, "sight_backward_m", true},
    {kSightMinM, "sight_min_m", true},
    {kRequiredSightM, "required_sight_m", true},
};

/// The reason codes roadcross-build stores (the runtime adds LOW_SCORE and OVERRIDE itself).
constexpr std::string_view kStoredReasonCodes[] = {"NOT_CROSSABLE_CLASS",
                                                   "TUNNEL",
                                                   "OVERRIDE",
                                                   "NEAR_JUNCTION",
                                                   "SHARP_BEND",
                                                   "CREST_OR_DIP",
                                                   "LIMITED_VISIBILITY",
                                                   "BUSY_ROAD",
                                                   "NO_ELEVATION",
                                                   "BRIDGE",
                                                   "COVERED",
                                                   "TOO_FAR_FROM_ROAD"};

/// What is wrong with the numbers of the current row of the `assessment` statement, or "".
std::string number_problem(const sqlite::Statement& row) {
  char text[160];
  for (const IntColumn& c : kIntColumns) {
    const int type = row.column_type(c.column);
    if (type == SQLITE_NULL && c.nullable) continue;
    const std::int64_t value = row.column_int64(c.column);
    if (type != SQLITE_INTEGER || value < c.min || value > c.max) {
      std::snprintf(text, sizeof text, "%s must be an integer in %lld..%lld", c.name,
                    static_cast<long long>(c.min), static_cast<long long>(c.max));
      return text;
    }
  }
  for (const RealColumn& c : kRealColumns) {
    const int type = row.column_type(c.column);
    if (type == SQLITE_NULL && c.nullable) continue;
    const double value = row.column_double(c.column);
    if ((type != SQLITE_FLOAT && type != SQLITE_INTEGER) || !std::isfinite(value) || value < 0.0) {
      std::snprintf(text, sizeof text, "%s must be a finite number >= 0", c.name);
      return text;
    }
  }
  const bool has_rank = row.column_type(kRank) != SQLITE_NULL;
  const bool has_score = row.column_type(kScore) != SQLITE_NULL;
  if (has_rank != has_score ||
      (has_rank && row.column_int64(kScore) != 15 - row.column_int64(kRank))) {
    return "score must be 15 - rank";
  }
  return {};
}

bool not_crossable_class(std::string_view highway) {
  const std::string_view base = highway.substr(0, highway.find("_link"));
  return base == "motorway" || base == "trunk";
}

/// What is wrong with the reasons of a judged row, or "": unknown codes and flags that
/// contradict the codes (a flipped tunnel bit must not make a tunnel suitable).
std::string reason_problem(const Assessment& a, bool no_crossing) {
  for (const std::string& code : a.reasons) {
    if (std::find(std::begin(kStoredReasonCodes), std::end(kStoredReasonCodes), code) ==
        std::end(kStoredReasonCodes)) {
      return "unknown reason code '" + code + "'";
    }
  }
  if (a.tunnel != has(a.reasons, "TUNNEL")) return "the tunnel flag contradicts its reasons";
  if (no_crossing && !has(a.reasons, "OVERRIDE")) {
    return "override_no_crossing is set but OVERRIDE is not among its reasons";
  }
  if (not_crossable_class(a.road.highway) != has(a.reasons, "NOT_CROSSABLE_CLASS")) {
    return "highway=" + a.road.highway + " contradicts NOT_CROSSABLE_CLASS in its reasons";
  }
  return {};
}

}  // namespace

namespace {

// Reads the segment's identity and cost terms (one primary-key read of the `assessment`
// statement) into `a` and applies the suitability rule. a.road.segment_id, a.road.distance_m and
// the thresholds must be set. The one place the rule lives: assess and assess_segment both
// judge through it, so that a map view can never disagree with assess.
Status judge(sqlite::Statement& row, Assessment& a, bool limited_visibility_unsuitable) {
  row.bind(1, a.road.segment_id);
  if (!row.step()) {
    row.reset();
    return Status{StatusCode::not_found,
                  "no segment with fid " + std::to_string(a.road.segment_id)};
  }
  a.road.osm_way_id = row.column_int64(0);
  a.road.highway = detail::valid_utf8(row.column_text_view(1));
  a.road.name = detail::valid_utf8(row.column_text_view(2));
  a.road.segment_length_m = row.column_double(3);
  a.class_cost = optional_int(row, 4);
  a.junction_distance_m = optional_double(row, 5);
  a.radius_m = optional_double(row, 6);
  a.curvature_level = optional_int(row, 7);
  a.curvature_cost = optional_int(row, 8);
  a.elevation_cost = optional_int(row, 9);
  if (!row.column_is_null(10)) a.landform.emplace(detail::valid_utf8(row.column_text_view(10)));
  a.maxspeed_kmh = optional_double(row, 11);
  a.lanes = optional_int(row, 12);
  a.width_m = optional_double(row, 13);
  a.context_score = optional_int(row, 14);
  a.crossing_distance_m = optional_double(row, 15);
  a.rank = optional_int(row, 16);
  a.score = optional_int(row, 17);
  // Room for the codes added below (TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE).
  split_codes(row.column_text_view(18), a.reasons, 4);
  a.tunnel = row.column_int64(19) != 0;
  a.override_note = detail::valid_utf8(row.column_text_view(20));
  const bool no_crossing = row.column_int64(21) != 0;
  const bool force_suitable = row.column_int64(22) != 0;
  a.sight_forward_m = optional_double(row, 23);
  a.sight_backward_m = optional_double(row, 24);
  a.sight_min_m = optional_double(row, 25);
  a.required_sight_m = optional_double(row, 26);
  std::string problem = number_problem(row);
  row.reset();
  if (problem.empty()) problem = reason_problem(a, no_crossing);
  if (!problem.empty()) {
    throw detail::corrupt_segment_error("segment " + std::to_string(a.road.segment_id) +
                                        " (OSM way " + std::to_string(a.road.osm_way_id) +
                                        "): " + problem);
  }

  a.valid = a.road.distance_m <= a.valid_distance_m;
  if (!a.valid) a.reasons.insert(a.reasons.begin(), "TOO_FAR_FROM_ROAD");
  if (!a.elevation_cost && !has(a.reasons, "NO_ELEVATION")) a.reasons.emplace_back("NO_ELEVATION");
  // Both in range (number_problem), so the sum fits an int.
  const int total = a.score.value_or(0) + a.context_score.value_or(0);
  const bool forbidden = has(a.reasons, "NOT_CROSSABLE_CLASS") || a.tunnel || no_crossing;
  const bool hidden = limited_visibility_unsuitable && has(a.reasons, "LIMITED_VISIBILITY");
  const bool good_enough = a.score.has_value() && total >= a.threshold;
  if (!good_enough && !force_suitable) a.reasons.emplace_back("LOW_SCORE");
  if ((no_crossing || force_suitable) && !has(a.reasons, "OVERRIDE"))
    a.reasons.emplace_back("OVERRIDE");
  // An operator's force_suitable overrides the score and the computed sight distance (the
  // operator may know of a mirror, or of a hedge cut back), never the class, a tunnel or
  // validity.
  a.suitable = a.valid && !forbidden && ((good_enough && !hidden) || force_suitable);
  return Status{};
}

}  // namespace

Result<Assessment> Map::assess(const Position& position, const AssessOptions& options) noexcept {
  Status checked = detail::check_assess_options(options);
  if (!checked.ok()) return Result<Assessment>{std::move(checked), std::nullopt};
  Impl& impl = *impl_;
  impl.budget->restart();
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    Status status = impl.locate(position, options.max_distance_m, a.road);
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
    status = judge(impl.queries.assessment, a, impl.thresholds.limited_visibility_unsuitable);
    if (status.code == StatusCode::not_found) {
      status = Status{StatusCode::corrupt_database, impl.info.path + ": segment without a row"};
    }
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    return result;
  } catch (const std::exception& e) {
    impl.queries.candidates.reset();
    impl.queries.assessment.reset();
    return Result<Assessment>{detail::status_of(e, impl.info.path), std::nullopt};
  }
}

Result<Assessment> Map::assess_segment(std::int64_t segment_id,
                                       const AssessOptions& options) noexcept {
  Status checked = detail::check_assess_options(options);
  if (!checked.ok()) return Result<Assessment>{std::move(checked), std::nullopt};
  Impl& impl = *impl_;
  impl.budget->restart();
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
    a.road.segment_id = segment_id;
    a.road.distance_m = 0.0;  // standing on the centreline
    Status status =
        judge(impl.queries.assessment, a, impl.thresholds.limited_visibility_unsuitable);
    if (!status.ok()) {
      status.message = impl.info.path + ": " + status.message;
      return Result<Assessment>{std::move(status), std::nullopt};
    }
    return result;
  } catch (const std::exception& e) {
    impl.queries.assessment.reset();
    return Result<Assessment>{detail::status_of(e, impl.info.path), std::nullopt};
  }
}

}  // namespace roadcross
