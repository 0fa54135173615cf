// JSON forms of the runtime's answers, shared by the subcommands and the batch mode so that a
// field means the same thing everywhere.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "roadcross/map_set.hpp"
#include "roadcross/runtime.hpp"

namespace roadcross::cli {

/// The value, or JSON null when it is absent (a term the DB does not have, a margin never set).
template <typename T>
nlohmann::ordered_json or_null(const std::optional<T>& value) {
  return value ? nlohmann::ordered_json(*value) : nlohmann::ordered_json(nullptr);
}

/// The JSON text of `value` (compact, or indented by `indent` spaces): every string byte sequence
/// that is not valid UTF-8 (a binary batch line, a damaged name in a map, a path in another
/// encoding) becomes U+FFFD instead of aborting the program, since JSON must be UTF-8. Every
/// JSON the roadcross CLI prints goes through this.
template <typename Json>
std::string json_text(const Json& value, int indent = -1) {
  return value.dump(indent, ' ', false, Json::error_handler_t::replace);
}

/// [latitude, longitude] in WGS84 degrees of a UTM point of the map's `zone`: every answer that
/// gives a position in UTM gives it in latitude/longitude beside it ("..._lat_lon_deg").
nlohmann::ordered_json lat_lon_json(const geo::UtmZone& zone, const PlanePoint& point);

// The answers; `zone` is the UTM zone of the map that answered (for the latitude/longitude
// fields).
nlohmann::ordered_json road_json(const NearestRoad& road, const geo::UtmZone& zone);
nlohmann::ordered_json heading_json(const RoadHeading& heading, const geo::UtmZone& zone);
nlohmann::ordered_json region_json(const UncertaintyRegion& region);
nlohmann::ordered_json assessment_json(const Assessment& assessment, const geo::UtmZone& zone);
nlohmann::ordered_json better_places_json(const BetterPlaces& places, const geo::UtmZone& zone);
/// {"path": ..., "map_id": ... or null}: which map of a set answered.
nlohmann::ordered_json map_source_json(const MapSource& source);
/// `answer` with a "map" member naming the map of a set that gave it (when `source` is set).
nlohmann::ordered_json with_map_source(nlohmann::ordered_json answer, const MapSource* source);

}  // namespace roadcross::cli
