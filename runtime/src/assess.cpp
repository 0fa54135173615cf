// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "map_impl.hpp"
#include "roadcross/schema/reasons.hpp"

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
                                                 C::required_sight_m};

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
  // Room for the codes added below (TOO_FAR_FROM_ROAD, NO_ELEVATION, LOW_SCORE, OVERRIDE).
  split_codes(row.column_text_view(at[C::reasons]), a.reasons, 4);
  a.tunnel = row.column_int64(at[C::tunnel]) != 0;
  a.override_note = row.column_text_view(at[C::override_note]);
  const bool no_crossing = row.column_int64(at[C::override_no_crossing]) != 0;
  const bool force_suitable = row.column_int64(at[C::override_force_suitable]) != 0;
  a.sight_forward_m = optional_double(row, C::sight_forward_m);
  a.sight_backward_m = optional_double(row, C::sight_backward_m);
  a.sight_min_m = optional_double(row, C::sight_min_m);
  a.required_sight_m = optional_double(row, C::required_sight_m);
  row.reset();

  a.valid = a.road.distance_m <= a.valid_distance_m;
  if (!a.valid) a.reasons.insert(a.reasons.begin(), "TOO_FAR_FROM_ROAD");
  if (!a.elevation_cost && !has(a.reasons, "NO_ELEVATION")) a.reasons.emplace_back("NO_ELEVATION");
  const int total = a.score.value_or(0) + a.context_score.value_or(0);
  const bool forbidden =
      has(a.reasons, "NOT_CROSSABLE_CLASS") || has(a.reasons, "TUNNEL") || a.tunnel || no_crossing;
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
  if (!(options.max_distance_m > 0.0)) {
    return Result<Assessment>{Status{StatusCode::invalid_argument, "max_distance_m must be > 0"},
                              std::nullopt};
  }
  Impl& impl = *impl_;
  try {
    Result<Assessment> result{Status{}, std::optional<Assessment>(std::in_place)};
    Assessment& a = *result.value;
    const double reach_m =
        position.uncertainty ? detail::region_reach_m(*position.uncertainty) : 0.0;
    Status status = impl.locate(position, options.max_distance_m, a.road, reach_m);
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    a.valid_distance_m = options.valid_distance_m.value_or(impl.thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl.thresholds.threshold);
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
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl.info.path + ": " + e.what()}, std::nullopt};
  }
}

Result<Assessment> Map::assess_segment(std::int64_t segment_id,
                                       const AssessOptions& options) noexcept {
  Impl& impl = *impl_;
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
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl.info.path + ": " + e.what()}, std::nullopt};
  }
}

}  // namespace roadcross
