// JSON forms of the runtime's answers, shared by the subcommands and the batch mode so that a
// field means the same thing everywhere.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>

#include "roadcross/runtime.hpp"

namespace roadcross::cli {

/// The value, or JSON null when it is absent (a term the DB does not have, a margin never set).
template <typename T>
nlohmann::ordered_json or_null(const std::optional<T>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

nlohmann::ordered_json road_json(const NearestRoad& road);
nlohmann::ordered_json heading_json(const RoadHeading& heading);
nlohmann::ordered_json region_json(const UncertaintyRegion& region);
nlohmann::ordered_json assessment_json(const Assessment& assessment);
nlohmann::ordered_json better_places_json(const BetterPlaces& places);

}  // namespace roadcross::cli
