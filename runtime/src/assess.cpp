// Map::assess: the segment's cost terms read from the DB, judged against the thresholds.
#include <algorithm>
#include <cstdlib>

#include "map_impl.hpp"

namespace roadcross {
namespace detail {

namespace {
// Columns read by assess, in this order (see schema/src/schema.cpp for meanings and units).
constexpr const char* kCostColumns =
    "class_cost, junction_distance_m, radius_m, curvature_level, curvature_cost, elevation_cost, "
    "landform, maxspeed_kmh, lanes, width_m, context_score, crossing_distance_m, rank, score, "
    "reasons, tunnel, override_note, override_no_crossing, override_force_suitable";
}  // namespace

Queries::Queries(sqlite::Database& db)
    : candidates(db.prepare("SELECT s.fid, s.geom FROM " + std::string(schema::kSegmentsRtree) +
                            " r JOIN " + std::string(schema::kSegmentsTable) +
                            " s ON s.fid = r.id WHERE r.maxx >= ?1 AND r.minx <= ?2 AND "
                            "r.maxy >= ?3 AND r.miny <= ?4")),
      attributes(db.prepare("SELECT osm_way_id, highway, name, length_m FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")),
      cost_terms(db.prepare(std::string("SELECT ") + kCostColumns + " FROM " +
                            std::string(schema::kSegmentsTable) + " WHERE fid = ?1")) {}

Thresholds thresholds_from(const MapInfo& info) {
  Thresholds t;
  for (const auto& [key, value] : info.metadata) {
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (end == value.c_str()) continue;
    if (key == "param.suitability.valid_distance_m") t.valid_distance_m = number;
    if (key == "param.suitability.threshold") t.threshold = number;
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
  return "see docs/cost-model.md";
}

namespace {

template <typename T>
std::optional<T> optional_column(const sqlite::Statement& row, int i) {
  if (row.column_is_null(i)) return std::nullopt;
  if constexpr (std::is_same_v<T, int>) {
    return static_cast<int>(row.column_int64(i));
  } else if constexpr (std::is_same_v<T, double>) {
    return row.column_double(i);
  } else {
    return row.column_text(i);
  }
}

void split_codes(const std::string& text, std::vector<std::string>& out) {
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(',', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
}

bool has(const std::vector<std::string>& codes, const char* code) {
  return std::find(codes.begin(), codes.end(), code) != codes.end();
}

}  // namespace

namespace {

// Reads the segment's cost terms into `a` and applies the suitability rule. `a.road` (and so
// a.road.distance_m) and the thresholds must be set. The one place the rule lives: assess and
// assess_segment both judge through it, so that a map view can never disagree with assess.
Status judge(sqlite::Statement& row, Assessment& a) {
  row.bind(1, a.road.segment_id);
  if (!row.step()) {
    row.reset();
    return Status{StatusCode::not_found,
                  "no segment with fid " + std::to_string(a.road.segment_id)};
  }
  a.class_cost = optional_column<int>(row, 0);
  a.junction_distance_m = optional_column<double>(row, 1);
  a.radius_m = optional_column<double>(row, 2);
  a.curvature_level = optional_column<int>(row, 3);
  a.curvature_cost = optional_column<int>(row, 4);
  a.elevation_cost = optional_column<int>(row, 5);
  a.landform = optional_column<std::string>(row, 6);
  a.maxspeed_kmh = optional_column<double>(row, 7);
  a.lanes = optional_column<int>(row, 8);
  a.width_m = optional_column<double>(row, 9);
  a.context_score = optional_column<int>(row, 10);
  a.crossing_distance_m = optional_column<double>(row, 11);
  a.rank = optional_column<int>(row, 12);
  a.score = optional_column<int>(row, 13);
  split_codes(row.column_text(14), a.reasons);
  a.tunnel = row.column_int64(15) != 0;
  a.override_note = row.column_text(16);
  const bool no_crossing = row.column_int64(17) != 0;
  const bool force_suitable = row.column_int64(18) != 0;
  row.reset();

  a.valid = a.road.distance_m <= a.valid_distance_m;
  if (!a.valid) a.reasons.insert(a.reasons.begin(), "TOO_FAR_FROM_ROAD");
  if (!a.elevation_cost && !has(a.reasons, "NO_ELEVATION")) a.reasons.emplace_back("NO_ELEVATION");
  const int total = a.score.value_or(0) + a.context_score.value_or(0);
  const bool forbidden = has(a.reasons, "NOT_CROSSABLE_CLASS") || a.tunnel || no_crossing;
  const bool good_enough = a.score.has_value() && total >= a.threshold;
  if (!good_enough && !force_suitable) a.reasons.emplace_back("LOW_SCORE");
  if ((no_crossing || force_suitable) && !has(a.reasons, "OVERRIDE"))
    a.reasons.emplace_back("OVERRIDE");
  // An operator's force_suitable overrides the score, never the class, a tunnel or validity.
  a.suitable = a.valid && !forbidden && (good_enough || force_suitable);
  return Status{};
}

}  // namespace

Result<Assessment> Map::assess(const Position& position, const AssessOptions& options) noexcept {
  Result<NearestRoad> road = nearest(position, options.max_distance_m);
  if (!road.ok()) return Result<Assessment>{road.status, std::nullopt};
  try {
    Assessment a;
    a.valid_distance_m = options.valid_distance_m.value_or(impl_->thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl_->thresholds.threshold);
    a.road = std::move(*road);
    Status status = judge(impl_->queries.cost_terms, a);
    if (status.code == StatusCode::not_found) {
      status = Status{StatusCode::corrupt_database, impl_->info.path + ": segment without a row"};
    }
    if (!status.ok()) return Result<Assessment>{std::move(status), std::nullopt};
    return Result<Assessment>{Status{}, std::move(a)};
  } catch (const std::exception& e) {
    impl_->queries.cost_terms.reset();
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl_->info.path + ": " + e.what()}, std::nullopt};
  }
}

Result<Assessment> Map::assess_segment(std::int64_t segment_id,
                                       const AssessOptions& options) noexcept {
  try {
    Assessment a;
    a.valid_distance_m = options.valid_distance_m.value_or(impl_->thresholds.valid_distance_m);
    a.threshold = options.threshold.value_or(impl_->thresholds.threshold);
    a.road.segment_id = segment_id;
    a.road.distance_m = 0.0;  // standing on the centreline
    sqlite::Statement& attributes = impl_->queries.attributes;
    attributes.bind(1, segment_id);
    if (attributes.step()) {
      a.road.osm_way_id = attributes.column_int64(0);
      a.road.highway = attributes.column_text(1);
      a.road.name = attributes.column_text(2);
      a.road.segment_length_m = attributes.column_double(3);
    }
    attributes.reset();
    Status status = judge(impl_->queries.cost_terms, a);
    if (!status.ok()) {
      status.message = impl_->info.path + ": " + status.message;
      return Result<Assessment>{std::move(status), std::nullopt};
    }
    return Result<Assessment>{Status{}, std::move(a)};
  } catch (const std::exception& e) {
    impl_->queries.attributes.reset();
    impl_->queries.cost_terms.reset();
    return Result<Assessment>{
        Status{StatusCode::corrupt_database, impl_->info.path + ": " + e.what()}, std::nullopt};
  }
}

}  // namespace roadcross
