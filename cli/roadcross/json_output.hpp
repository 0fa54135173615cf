// JSON forms of the runtime's answers, shared by the subcommands and the batch mode so that a
// field means the same thing everywhere.
#pragma once

#include <nlohmann/json.hpp>

#include "roadcross/runtime.hpp"

namespace roadcross::cli {

nlohmann::ordered_json road_json(const NearestRoad& road);
nlohmann::ordered_json heading_json(const RoadHeading& heading);
nlohmann::ordered_json assessment_json(const Assessment& assessment);
nlohmann::ordered_json better_places_json(const BetterPlaces& places);

}  // namespace roadcross::cli
