// The latitude/longitude box of a stretch of the UTM grid: how a set of maps (MapSet) finds
// the maps that may cover a position without projecting it into every map's zone.
#pragma once

#include "roadcross/geo.hpp"

namespace roadcross::geo {

/// A box of WGS84 latitudes and longitudes, degrees (min <= max; not across the antimeridian).
struct LatLonBox {
  double min_lat_deg = 0.0, min_lon_deg = 0.0, max_lat_deg = 0.0, max_lon_deg = 0.0;
  bool contains(double lat_deg, double lon_deg) const noexcept {
    return lat_deg >= min_lat_deg && lat_deg <= max_lat_deg && lon_deg >= min_lon_deg &&
           lon_deg <= max_lon_deg;
  }
};

/// The latitude/longitude box of a rectangle of the UTM grid (metres, min <= max): the box of
/// 129 points along each side, grown by 1e-5 degrees (about 1 m). The projection is smooth and
/// invertible, so latitude and longitude take their extremes on the rectangle's sides; between
/// two points a side's latitude or longitude strays from theirs by less than 4e-6 degrees for
/// sides up to 500 km (the parallels' curvature in the grid), which the margin covers.
LatLonBox wgs84_box_of_utm_rectangle(UtmZone zone, double min_easting_m, double min_northing_m,
                                     double max_easting_m, double max_northing_m);

}  // namespace roadcross::geo
