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

/// [latitude, longitude] in WGS84 degrees of a UTM point of the map's `zone`: every answer that
/// gives a position in UTM gives it in latitude/longitude beside it ("..._lat_lon_deg").
nlohmann::ordered_json lat_lon_json(const geo::UtmZone& zone, const PlanePoint& point);

// The answers; `zone` is the map's UTM zone (for the latitude/longitude fields).
nlohmann::ordered_json road_json(const NearestRoad& road, const geo::UtmZone& zone);
nlohmann::ordered_json heading_json(const RoadHeading& heading, const geo::UtmZone& zone);
nlohmann::ordered_json assessment_json(const Assessment& assessment, const geo::UtmZone& zone);
nlohmann::ordered_json better_places_json(const BetterPlaces& places, const geo::UtmZone& zone);

}  // namespace roadcross::cli
