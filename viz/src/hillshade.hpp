// A hillshade of the terrain coverage stored in the DB, for the picture's background.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/viz/layers.hpp"

namespace roadcross::viz {

/// Grey shades in Cairo's ARGB32 layout (premultiplied; alpha 0 where the grid has no data),
/// north-up, one pixel per grid cell.
struct ShadeImage {
  int width = 0, height = 0;
  double west_m = 0.0, north_m = 0.0;  ///< UTM of the image's top-left corner
  double cell_m = 0.0;                 ///< cell size, metres (square cells)
  std::vector<std::uint32_t> argb;
};

/// Horn's hillshade (sun at azimuth 315 deg, altitude 45 deg, vertical exaggeration 2) of the
/// part of GPKG:db:terrain that covers `area`; nullopt when it does not cover it. Throws when
/// GDAL cannot read the coverage.
std::optional<ShadeImage> hillshade(const std::string& db_path, const UtmBox& area);

/// A shade image in Web Mercator (what web maps draw), north-up, covering a WGS84 box.
struct MercatorShade {
  ShadeImage image;  ///< west_m/north_m/cell_m unused
  double west_lon_deg = 0.0, south_lat_deg = 0.0, east_lon_deg = 0.0, north_lat_deg = 0.0;
};

/// The hillshade of `area` resampled (nearest cell) into Web Mercator, at most `max_width_px`
/// wide, for the viewer's image overlay; nullopt when the terrain does not cover `area`.
std::optional<MercatorShade> mercator_hillshade(const std::string& db_path, const UtmBox& area,
                                                const geo::UtmZone& zone, int max_width_px);

}  // namespace roadcross::viz
