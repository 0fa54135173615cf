#include "json_output.hpp"

#include <cmath>

#include "roadcross/geo.hpp"

namespace roadcross::cli {

nlohmann::ordered_json lat_lon_json(const geo::UtmZone& zone, const PlanePoint& point) {
  const geo::LatLon p = geo::utm_to_wgs84(point.easting_m, point.northing_m, zone);
  // 7 decimals of a degree: about 1 cm, finer than any position in a map.
  const auto round7 = [](double deg) { return std::round(deg * 1e7) / 1e7; };
  return {round7(p.lat_deg), round7(p.lon_deg)};
}

nlohmann::ordered_json road_json(const NearestRoad& road, const geo::UtmZone& zone) {
  nlohmann::ordered_json out;
  out["segment_id"] = road.segment_id;
  out["osm_way_id"] = road.osm_way_id;
  out["highway"] = road.highway;
  out["name"] = road.name;
  out["distance_m"] = road.distance_m;
  out["query_utm_m"] = {road.query.easting_m, road.query.northing_m};
  out["query_lat_lon_deg"] = lat_lon_json(zone, road.query);
  out["closest_utm_m"] = {road.closest.easting_m, road.closest.northing_m};
  out["closest_lat_lon_deg"] = lat_lon_json(zone, road.closest);
  return out;
}

nlohmann::ordered_json heading_json(const RoadHeading& h, const geo::UtmZone& zone) {
  nlohmann::ordered_json out = road_json(h.road, zone);
  out["road_heading_rad"] = h.road_heading_rad;
  out["road_bearing_deg"] = h.road_bearing_deg;
  out["crossing_heading_rad"] = h.crossing_heading_rad;
  out["crossing_bearing_deg"] = h.crossing_bearing_deg;
  out["convergence_rad"] = h.convergence_rad;
  out["on_centreline"] = h.on_centreline;
  if (h.heading_spread_rad) out["heading_spread_rad"] = *h.heading_spread_rad;
  return out;
}

nlohmann::ordered_json region_json(const UncertaintyRegion& r) {
  nlohmann::ordered_json out;
  out["region_probability"] = r.region_probability;
  out["semi_major_m"] = r.semi_major_m;
  out["semi_minor_m"] = r.semi_minor_m;
  out["major_axis_yaw_rad"] = r.major_axis_yaw_rad;
  out["segment_ids"] = r.segment_ids;
  out["same_road"] = r.same_road;
  out["suitable_share"] = r.suitable_share;
  out["heading_spread_rad"] = r.heading_spread_rad;
  return out;
}

nlohmann::ordered_json assessment_json(const Assessment& a, const geo::UtmZone& zone) {
  nlohmann::ordered_json out;
  out["valid"] = a.valid;
  out["suitable"] = a.suitable;
  out["segment_id"] = a.road.segment_id;
  out["osm_way_id"] = a.road.osm_way_id;
  out["highway"] = a.road.highway;
  out["name"] = a.road.name;
  out["distance_m"] = a.road.distance_m;
  out["closest_utm_m"] = {a.road.closest.easting_m, a.road.closest.northing_m};
  out["closest_lat_lon_deg"] = lat_lon_json(zone, a.road.closest);
  out["score"] = or_null(a.score);
  out["context_score"] = or_null(a.context_score);
  out["threshold"] = a.threshold;
  out["valid_distance_m"] = a.valid_distance_m;
  out["rank"] = or_null(a.rank);
  out["class_cost"] = or_null(a.class_cost);
  out["curvature_cost"] = or_null(a.curvature_cost);
  out["curvature_level"] = or_null(a.curvature_level);
  out["radius_m"] = or_null(a.radius_m);
  out["junction_distance_m"] = or_null(a.junction_distance_m);
  out["elevation_cost"] = or_null(a.elevation_cost);
  out["landform"] = or_null(a.landform);
  out["maxspeed_kmh"] = or_null(a.maxspeed_kmh);
  out["lanes"] = or_null(a.lanes);
  out["width_m"] = or_null(a.width_m);
  out["crossing_distance_m"] = or_null(a.crossing_distance_m);
  out["sight_forward_m"] = or_null(a.sight_forward_m);
  out["sight_backward_m"] = or_null(a.sight_backward_m);
  out["sight_min_m"] = or_null(a.sight_min_m);
  out["required_sight_m"] = or_null(a.required_sight_m);
  out["tunnel"] = a.tunnel;
  out["kerb"] = or_null(a.kerb);
  out["kerb_height_m"] = or_null(a.kerb_height_m);
  out["max_kerb_height_m"] = a.max_kerb_height_m;
  out["crossing_island"] = or_null(a.crossing_island);
  out["sidewalk_left"] = or_null(a.sidewalk_left);
  out["sidewalk_right"] = or_null(a.sidewalk_right);
  out["robot_side"] = a.robot_side;  // +1 left of the way's direction, -1 right, 0 unknown
  out["pavement_far_side"] = or_null(a.pavement_far_side);
  out["override_note"] = a.override_note;
  out["reasons"] = a.reasons;
  if (a.region) out["region"] = region_json(*a.region);
  return out;
}

nlohmann::ordered_json better_places_json(const BetterPlaces& places, const geo::UtmZone& zone) {
  nlohmann::ordered_json out;
  out["candidates"] = nlohmann::ordered_json::array();
  for (const Candidate& c : places.candidates) {
    out["candidates"].push_back({{"point_utm_m", {c.point.easting_m, c.point.northing_m}},
                                 {"point_lat_lon_deg", lat_lon_json(zone, c.point)},
                                 {"walking_distance_m", c.walking_distance_m},
                                 {"segment_id", c.segment_id},
                                 {"suitable", c.suitable},
                                 {"score_plus_context", c.score},
                                 {"designated_crossing", c.designated_crossing},
                                 {"crossing_heading_rad", c.crossing_heading_rad},
                                 {"reasons", c.reasons}});
    if (c.suitable_share) out["candidates"].back()["suitable_share"] = *c.suitable_share;
  }
  out["reason"] = places.reason;
  return out;
}

nlohmann::ordered_json map_source_json(const MapSource& source) {
  nlohmann::ordered_json out;
  out["path"] = source.path;
  out["map_id"] = source.map_id.empty() ? nlohmann::ordered_json(nullptr)
                                        : nlohmann::ordered_json(source.map_id);
  return out;
}

nlohmann::ordered_json with_map_source(nlohmann::ordered_json answer, const MapSource* source) {
  if (source) answer["map"] = map_source_json(*source);
  return answer;
}

}  // namespace roadcross::cli
