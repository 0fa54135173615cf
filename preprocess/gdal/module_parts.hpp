// The GDAL module's parts (libroadcross_gdal.so, see common/gdal_module.hpp), each in its own
// file of this folder, and what they share.
#pragma once

#include <cpl_error.h>

#include <memory>
#include <string>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/common/gdal_module.hpp"

namespace roadcross::preprocess::gdal {

/// crs_transform.cpp
std::unique_ptr<CrsTransformBackend> make_crs_transform(const std::string& crs,
                                                        const geo::UtmZone& zone);
/// raster_elevation.cpp
std::unique_ptr<RasterBackend> open_raster(const std::string& path, const geo::UtmZone& zone);
/// terrain_coverage.cpp
void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                            const std::string& last_change);

/// Makes GDAL's messages go into our errors (which name the file), not raw onto stderr, for the
/// lifetime of the guard (GDAL's handler stack is per thread).
struct QuietGdal {
  QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
};

}  // namespace roadcross::preprocess::gdal
