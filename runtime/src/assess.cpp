// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "map_impl.hpp"
#include "roadcross/schema/reasons.hpp"
#include "roadcross/schema/verdict.hpp"

namespace roadcross {
namespace detail {

using C = schema::SegmentColumn;

// What assess reads of a segment: its identity (as nearest() reads it), then its cost terms.
const schema::SegmentSelection kAssessColumns = {C::osm_way_id,
                                                 C::highway,
                                                 C::name,
                                                 C::length_m,
                                                 C::class_cost,
                                                 C::junction_distance_m,
                                                 C::radius_m,
                                                 C::curvature_level,
                                                 C::curvature_cost,
                                                 C::elevation_cost,
                                                 C::landform,
                                                 C::maxspeed_kmh,
                                                 C::lanes,
                                                 C::width_m,
                                                 C::context_score,
                                                 C::crossing_distance_m,
                                                 C::rank,
                                                 C::score,
                                                 C::reasons,
                                                 C::tunnel,
                                                 C::override_note,
                                                 C::override_no_crossing,
                                                 C::override_force_suitable,
                                                 C::sight_forward_m,
                                                 C::sight_backward_m,
                                                 C::sight_min_m,
                                                 C::required_sight_m,
                                                 C::kerb,
                                                 C::kerb_height_m,
                                                 C::crossing_island,
                                                 C::sidewalk_left,
                                                 C::sidewalk_right};

const schema::SegmentSelection kIdentityColumns = {C::osm_way_id, C::highway, C::name, C::length_m};
const schema::SegmentSelection kEndNodeColumns({C::from_node_id, C::to_node_id}, 2);

Queries::Queries(sqlite::Database& db, int schema_version)
    : candidates(db.prepare("SELECT s.fid, s.geom, r.minx, r.maxx, r.miny, r.maxy FROM " +
                            std::string(schema::kSegmentsRtree) + " r JOIN " +
                            std::string(schema::kSegmentsTable) +
                            " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                            "r.maxy >= ?3 AND r.miny <= ?4")),
      attributes(db.prepare("SELECT " + kIdentityColumns.sql("", schema_version) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      assessment(db.prepare("SELECT " + kAssessColumns.sql("", schema_version) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      rtree_holder(
          db.prepare("SELECT id FROM " + std::string(schema::kSegmentsRtree) + " LIMIT 1")),
      segments_at(db.prepare("SELECT s.fid, s.geom, " + kEndNodeColumns.sql("s", schema_version) +
                             ", r.minx, r.maxx, r.miny, r.maxy FROM " +
                             std::string(schema::kSegmentsRtree) + " r JOIN " +
                             std::string(schema::kSegmentsTable) +
                             " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                             "r.maxy >= ?3 AND r.miny <= ?4")) {
  rtree_holder.step();
}

Status thresholds_from(const MapInfo& info, Thresholds& out) {
  Thresholds t;
  for (const auto& [key, value] : info.metadata) {
    double* target = key == schema::meta::kValidDistanceParam   ? &t.valid_distance_m
                     : key == schema::meta::kThresholdParam     ? &t.threshold
                     : key == schema::meta::kMaxKerbHeightParam ? &t.max_kerb_height_m
                                                                : nullptr;
    const bool visibility = key == schema::meta::kLimitedVisibilityUnsuitableParam;
    if (!target && !visibility) continue;
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    const bool in_range = end != value.c_str() && *end == '\0' && std::isfinite(number) &&
                          (target == &t.threshold || number >= 0.0);
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
  if (options.max_kerb_height_m &&
      !(std::isfinite(*options.max_kerb_height_m) && *options.max_kerb_height_m >= 0.0)) {
    return {StatusCode::invalid_argument, "max_kerb_height_m must be a finite number >= 0 metres"};
  }
  return {};
}

}  // namespace detail

const char* describe_reason(const std::string& code) noexcept {
  const schema::ReasonSpec* spec = schema::find_reason(code);
  // The sentences are literals: their views end in a NUL.
  return spec ? spec->sentence.data() : "see docs/cost-model.md";
}

namespace {

using C = schema::SegmentColumn;
using detail::kAssessColumns;

std::optional<int> optional_int(const sqlite::Statement& row, schema::SegmentColumn column) {
  const int i = kAssessColumns[column];
  if (row.column_is_null(i)) return std::nullopt;
  return static_cast<int>(row.column_int64(i));
}

std::optional<double> optional_double(const sqlite::Statement& row, schema::SegmentColumn column) {
  const int i = kAssessColumns[column];
  if (row.column_is_null(i)) return std::nullopt;
  return row.column_double(i);
}

std::optional<bool> optional_flag(const sqlite::Statement& row, schema::SegmentColumn column) {
  const int i = kAssessColumns[column];
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

/// Integer columns and the values roadcross-build writes (docs/cost-model.md; the flags are 0
/// or 1). context_score's bound is far beyond any parameter file's, and keeps score +
/// context_score inside int.
struct IntColumn {
  schema::SegmentColumn column;
  const char* name;
  std::int64_t min, max;
  bool nullable;
};
const IntColumn kIntColumns[] = {
    {C::osm_way_id, "osm_way_id", INT64_MIN, INT64_MAX, false},
    {C::class_cost, "class_cost", 0, 5, true},
    {C::curvature_level, "curvature_level", 0, 5, true},
    {C::curvature_cost, "curvature_cost", 0, 14, true},
    {C::elevation_cost, "elevation_cost", 0, 9, true},
    {C::lanes, "lanes", 0, 1000, true},
    {C::context_score, "context_score", -1000000, 1000000, true},
    {C::rank, "rank", 0, 14, true},
    {C::score, "score", 1, 15, true},
    {C::tunnel, "tunnel", 0, 1, false},
    {C::override_no_crossing, "override_no_crossing", 0, 1, false},
    {C::override_force_suitable, "override_force_suitable", 0, 1, false},
    {C::crossing_island, "crossing_island", 0, 1, true},
    {C::sidewalk_left, "sidewalk_left", 0, 1, true},
    {C::sidewalk_right, "sidewalk_right", 0, 1, true},
};

/// Distances, speeds and widths: finite and >= 0 where present (length_m always present).
struct RealColumn {
  schema::SegmentColumn column;
  const char* name;
  bool nullable;
};
const RealColumn kRealColumns[] = {
    {C::length_m, "length_m", false},
    {C::junction_distance_m, "junction_distance_m", true},
    {C::radius_m, "radius_m", true},
    {C::maxspeed_kmh, "maxspeed_kmh", true},
    {C::width_m, "width_m", true},
    {C::crossing_distance_m, "crossing_distance_m", true},
    {C::sight_forward_m, "sight_forward_m", true},
    {C::sight_backward_m, "sight_backward_m", true},
    {C::sight_min_m, "sight_min_m", true},
    {C::required_sight_m, "required_sight_m", true},
    {C::kerb_height_m, "kerb_height_m", true},
};

/// What is wrong with the numbers of the current row of the `assessment` statement, or "".
std::string number_problem(const sqlite::Statement& row) {
  const schema::SegmentSelection& at = detail::kAssessColumns;
  char text[160];
  for (const IntColumn& c : kIntColumns) {
    const int column = at[c.column];
    const int type = row.column_type(column);
    if (type == SQLITE_NULL && c.nullable) continue;
    const std::int64_t value = row.column_int64(column);
    if (type != SQLITE_INTEGER || value < c.min || value > c.max) {
      std::snprintf(text, sizeof text, "%s must be an integer in %lld..%lld", c.name,
                    static_cast<long long>(c.min), static_cast<long long>(c.max));
      return text;
    }
  }
  for (const RealColumn& c : kRealColumns) {
    const int column = at[c.column];
    const int type = row.column_type(column);
    if (type == SQLITE_NULL && c.nullable) continue;
    const double value = row.column_double(column);
    if ((type != SQLITE_FLOAT && type != SQLITE_INTEGER) || !std::isfinite(value) || value < 0.0) {
      std::snprintf(text, sizeof text, "%s must be a finite number >= 0", c.name);
      return text;
    }
  }
  const int rank = at[C::rank], score = at[C::score];
  const bool has_rank = row.column_type(rank) != SQLITE_NULL;
  const bool has_score = row.column_type(score) != SQLITE_NULL;
  if (has_rank != has_score ||
      (has_rank && row.column_int64(score) != 15 - row.column_int64(rank))) {
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
    const schema::ReasonSpec* spec = schema::find_reason(code);
    if (!spec || !spec->stored_by_build) {
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
// statement) into `a` and applies the suitability rule. a.road.segment_id, a.road.distance_m,
// a.robot_side, a.max_kerb_height_m and the thresholds must be set. The rule itself is
// schema::judge_segment with the robot's two rules (kerb, far pavement), which better_place
// applies too, so that no surface can disagree with assess.
Status judge(sqlite::Statement& row, Assessment& a, bool limited_visibility_unsuitable) {
  row.bind(1, a.road.segment_id);
  if (!row.step()) {
    row.reset();
    return Status{StatusCode::not_found,
                  "no segment with fid " + std::to_string(a.road.segment_id)};
  }
  const schema::SegmentSelection& at = kAssessColumns;
  a.road.osm_way_id = row.column_int64(at[C::osm_way_id]);
  a.road.highway = detail::valid_utf8(row.column_text_view(at[C::highway]));
  a.road.name = detail::valid_utf8(row.column_text_view(at[C::name]));
  a.road.segment_length_m = row.column_double(at[C::length_m]);
  a.class_cost = optional_int(row, C::class_cost);
  a.junction_distance_m = optional_double(row, C::junction_distance_m);
  a.radius_m = optional_double(row, C::radius_m);
  a.curvature_level = optional_int(row, C::curvature_level);
  a.curvature_cost = optional_int(row, C::curvature_cost);
  a.elevation_cost = optional_int(row, C::elevation_cost);
  if (!row.column_is_null(at[C::landform]))
    a.landform.emplace(detail::valid_utf8(row.column_text_view(at[C::landform])));
  a.maxspeed_kmh = optional_double(row, C::maxspeed_kmh);
  a.lanes = optional_int(row, C::lanes);
  a.width_m = optional_double(row, C::width_m);
  a.context_score = optional_int(row, C::context_score);
  a.crossing_distance_m = optional_double(row, C::crossing_distance_m);
  a.rank = optional_int(row, C::rank);
  a.score = optional_int(row, C::score);
  // Room for the codes added below (TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE,
  // KERB_TOO_HIGH, NO_PAVEMENT_FAR_SIDE).
  split_codes(row.column_text_view(at[C::reasons]), a.reasons, 6);
  a.tunnel = row.column_int64(at[C::tunnel]) != 0;
  a.override_note = detail::valid_utf8(row.column_text_view(at[C::override_note]));
  const bool no_crossing = row.column_int64(at[C::override_no_crossing]) != 0;
  const bool force_suitable = row.column_int64(at[C::override_force_suitable]) != 0;
  a.sight_forward_m = optional_double(row, C::sight_forward_m);
  a.sight_backward_m = optional_double(row, C::sight_backward_m);
  a.sight_min_m = optional_double(row, C::sight_min_m);
  a.required_sight_m = optional_double(row, C::required_sight_m);
  if (!row.column_is_null(at[C::kerb]))
    a.kerb.emplace(detail::valid_utf8(row.column_text_view(at[C::kerb])));
  a.kerb_height_m = optional_double(row, C::kerb_height_m);
  a.crossing_island = optional_flag(row, C::crossing_island);
  a.sidewalk_left = optional_flag(row, C::sidewalk_left);
  a.sidewalk_right = optional_flag(row, C::sidewalk_right);
  std::string problem = number_problem(row);
  // Judged before the reset (the reasons' text lives in the row); used only when the row's
  // numbers are in range (number_problem).
  const schema::Verdict verdict =
      schema::judge_segment({a.score, a.context_score, row.column_text_view(at[C::reasons]),
                             a.tunnel, no_crossing, force_suitable},
                            {a.threshold, limited_visibility_unsuitable});
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
  // What the robot cannot do: climb a kerb known to be higher than it can, or leave the road
  // onto a far side tagged without a pavement. Unknown (NULL) never forbids, and an operator's
  // force_suitable does not lift either.
  const bool kerb_too_high = a.kerb_height_m && *a.kerb_height_m > a.max_kerb_height_m + 1e-9;
  if (kerb_too_high) a.reasons.emplace_back("KERB_TOO_HIGH");
  if (a.robot_side != 0)
    a.pavement_far_side = a.robot_side > 0 ? a.sidewalk_right : a.sidewalk_left;
  const bool stranded = a.pavement_far_side.has_value() && !*a.pavement_far_side;
  if (stranded) a.reasons.emplace_back("NO_PAVEMENT_FAR_SIDE");
  if (verdict.low_score) a.reasons.emplace_back("LOW_SCORE");
  if ((no_crossing || force_suitable) && !has(a.reasons, "OVERRIDE"))
    a.reasons.emplace_back("OVERRIDE");
  a.suitable = a.valid && verdict.suitable && !kerb_too_high && !stranded;
  return Status{};
}

}  // namespace

Status Map::Impl::judge_region(const PositionUncertainty& uncertainty, Assessment& a) {
  Impl& impl = *this;
  detail::RegionGeometry geometry;
  Status status = region_geometry(uncertainty, a.road, geometry);
  if (!status.ok()) return status;
  UncertaintyRegion& region = a.region.emplace();
  region.region_probability = geometry.region_probability;
  region.semi_major_m = geometry.semi_major_m;
  region.semi_minor_m = geometry.semi_minor_m;
  region.major_axis_yaw_rad = geometry.major_axis_yaw_rad;
  region.heading_spread_rad = geometry.heading_spread_rad;

  // The fix's segment is judged on its centreline like the others: the fix's own distance
  // decides validity, the region decides which segments count.
  const auto judged_on_centreline = [&](std::int64_t segment_id, Assessment& out) {
    out.road.segment_id = segment_id;
    out.road.distance_m = 0.0;
    out.valid_distance_m = a.valid_distance_m;
    out.threshold = a.threshold;
    Status judged = judge(impl.region_verdict, out, impl.thresholds.limited_visibility_unsuitable);
    if (judged.code == StatusCode::not_found) {
      throw std::runtime_error("segment " + std::to_string(segment_id) + " has no row");
    }
  };
  bool fix_segment_suitable = a.suitable;
  if (!a.valid) {
    Assessment on_centreline;
    judged_on_centreline(a.road.segment_id, on_centreline);
    fix_segment_suitable = on_centreline.suitable;
  }
  const std::vector<detail::RegionSegment>& segments = impl.region_segments;
  std::size_t suitable_samples =
      fix_segment_suitable ? segments[geometry.fix_index].sample_count : 0;
  bool any_suitable = fix_segment_suitable, any_unsuitable = !fix_segment_suitable;
  region.segment_ids.push_back(a.road.segment_id);
  for (std::size_t i = 0; i < geometry.segment_count; ++i) {
    const detail::RegionSegment& s = segments[i];
    if (i == geometry.fix_index || (s.sample_count == 0 && !s.centreline_in_region)) continue;
    Assessment other;
    judged_on_centreline(s.id, other);
    region.segment_ids.push_back(s.id);
    if (other.suitable) {
      suitable_samples += s.sample_count;
      any_suitable = true;
    } else {
      any_unsuitable = true;
    }
    // One road: the same OSM way, or a way of the same name (a street split at its junctions).
    const bool same_way = other.road.osm_way_id == a.road.osm_way_id;
    const bool same_name = !a.road.name.empty() && other.road.name == a.road.name;
    if (!same_way && !same_name) region.same_road = false;
  }
  std::sort(region.segment_ids.begin() + 1, region.segment_ids.end());
  region.suitable_share =
      static_cast<double>(suitable_samples) / static_cast<double>(geometry.sample_count);
  a.suitable = a.suitable && !any_unsuitable && region.same_road;
  if (any_suitable && any_unsuitable) a.reasons.emplace_back("POSITION_UNCERTAIN");
  if (!region.same_road) a.reasons.emplace_back("AMBIGUOUS_ROAD");
  return {};
}

Result<Assessment> Map::assess(const Position& position, const AssessOptions& options) noexcept {
  Status checked = detail::check_assess_options(options);
  if (!checked.ok()) return Result<Assessment>{std::move(checked), std::nullopt};
  Impl& impl = *impl_;
  impl.budget->restart();
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    const double reach_m =
        position.uncertainty ? detail::region_reach_m(*position.uncertainty) : 0.0;
    Status status = impl.locate(position, options.max_distance_m, a.road, reach_m);
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
    a.max_kerb_height_m = options.max_kerb_height_m.value_or(impl.thresholds.max_kerb_height_m);
    a.robot_side = impl.side_of(a.road);
    status = judge(impl.queries.assessment, a, impl.thresholds.limited_visibility_unsuitable);
    if (status.code == StatusCode::not_found) {
      status = Status{StatusCode::corrupt_database, impl.info.path + ": segment without a row"};
    }
    if (status.ok() && position.uncertainty) status = impl.judge_region(*position.uncertainty, a);
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    return result;
  } catch (const std::exception& e) {
    impl.queries.candidates.reset();
    impl.queries.assessment.reset();
    impl.region_verdict.reset();
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
    return Result<Assessment>{detail::status_of(e, impl.info.path), std::nullopt};
  }
}

}  // namespace roadcross
