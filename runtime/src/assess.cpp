// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cmath>
#include <cstdlib>
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
    : candidates(db.prepare("SELECT s.fid, s.geom FROM " + std::string(schema::kSegmentsRtree) +
                            " r JOIN " + std::string(schema::kSegmentsTable) +
                            " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                            "r.maxy >= ?3 AND r.miny <= ?4")),
      attributes(db.prepare("SELECT " + kIdentityColumns.sql("", schema_version) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      assessment(db.prepare("SELECT " + kAssessColumns.sql("", schema_version) + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      rtree_holder(
          db.prepare("SELECT id FROM " + std::string(schema::kSegmentsRtree) + " LIMIT 1")),
      segments_at(db.prepare("SELECT s.fid, s.geom, " + kEndNodeColumns.sql("s", schema_version) +
                             " FROM " + std::string(schema::kSegmentsRtree) + " r JOIN " +
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
    if (key == schema::meta::kValidDistanceParam) t.valid_distance_m = number;
    if (key == schema::meta::kThresholdParam) t.threshold = number;
    if (key == schema::meta::kLimitedVisibilityUnsuitableParam)
      t.limited_visibility_unsuitable = number != 0.0;
    if (key == schema::meta::kMaxKerbHeightParam) t.max_kerb_height_m = number;
  }
  return t;
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
  a.road.highway = row.column_text_view(at[C::highway]);
  a.road.name = row.column_text_view(at[C::name]);
  a.road.segment_length_m = row.column_double(at[C::length_m]);
  a.class_cost = optional_int(row, C::class_cost);
  a.junction_distance_m = optional_double(row, C::junction_distance_m);
  a.radius_m = optional_double(row, C::radius_m);
  a.curvature_level = optional_int(row, C::curvature_level);
  a.curvature_cost = optional_int(row, C::curvature_cost);
  a.elevation_cost = optional_int(row, C::elevation_cost);
  if (!row.column_is_null(at[C::landform]))
    a.landform.emplace(row.column_text_view(at[C::landform]));
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
  a.override_note = row.column_text_view(at[C::override_note]);
  const bool no_crossing = row.column_int64(at[C::override_no_crossing]) != 0;
  const bool force_suitable = row.column_int64(at[C::override_force_suitable]) != 0;
  a.sight_forward_m = optional_double(row, C::sight_forward_m);
  a.sight_backward_m = optional_double(row, C::sight_backward_m);
  a.sight_min_m = optional_double(row, C::sight_min_m);
  a.required_sight_m = optional_double(row, C::required_sight_m);
  if (!row.column_is_null(at[C::kerb])) a.kerb.emplace(row.column_text_view(at[C::kerb]));
  a.kerb_height_m = optional_double(row, C::kerb_height_m);
  a.crossing_island = optional_flag(row, C::crossing_island);
  a.sidewalk_left = optional_flag(row, C::sidewalk_left);
  a.sidewalk_right = optional_flag(row, C::sidewalk_right);
  const schema::Verdict verdict =
      schema::judge_segment({a.score, a.context_score, row.column_text_view(at[C::reasons]),
                             a.tunnel, no_crossing, force_suitable},
                            {a.threshold, limited_visibility_unsuitable});
  row.reset();

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
