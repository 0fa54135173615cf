#include "roadcross/preprocess/parameters.hpp"

#include <charconv>
#include <cmath>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/schema/schema.hpp"

namespace roadcross::preprocess {

std::string format_number(double value) {
  char buffer[64];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("nan");
}

void SegmentParameters::describe(std::vector<ParameterSpec>& out) {
  out.push_back(
      {"segments", "max_segment_length_m", &max_segment_length_m, 0.1, 1000.0, false,
       "longest road segment, metres; pieces between junctions are cut into equal parts"});
}

void SuitabilityParameters::describe(std::vector<ParameterSpec>& out) {
  out.push_back({"suitability", "threshold", &threshold, -1000, 1000, false,
                 "suitable when score + context score >= this (thesis 20)"});
  out.push_back(
      {"suitability", "valid_distance_m", &valid_distance_m, 0, 1000, false,
       "a position is valid within this distance of a road centreline, metres (thesis 10)"});
  out.push_back({"suitability", "max_kerb_height_m", &max_kerb_height_m, 0, 1, false,
                 "highest kerb the robot climbs, metres: a higher known kerb is KERB_TOO_HIGH "
                 "(robot profiles in docs/profiles; 1 = no limit)"});
}

std::vector<ParameterSpec> Parameters::specs() {
  std::vector<ParameterSpec> out;
  segments.describe(out);
  geometry.describe(out);
  terrain.describe(out);
  rank.describe(out);
  context.describe(out);
  sight.describe(out);
  suitability.describe(out);
  return out;
}

void Parameters::validate() const {
  for (const ParameterSpec& spec : specs()) {
    const double v = *spec.value;
    if (!std::isfinite(v) || v < spec.min || v > spec.max) {
      throw ParameterError(spec.key() + " must be in [" + format_number(spec.min) + ", " +
                           format_number(spec.max) + "], got " + format_number(v));
    }
    if (spec.integer && v != std::floor(v)) {
      throw ParameterError(spec.key() + " must be a whole number, got " + format_number(v));
    }
  }
  geometry.validate_relations();
  terrain.validate_relations();
}

std::vector<std::pair<std::string, std::string>> Parameters::as_metadata() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const ParameterSpec& spec : specs()) {
    out.emplace_back(std::string(schema::meta::kParamPrefix) + spec.key(),
                     format_number(*spec.value));
  }
  return out;
}

}  // namespace roadcross::preprocess
