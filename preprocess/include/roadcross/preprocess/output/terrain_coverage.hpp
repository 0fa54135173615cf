// The terrain grid stored in the output GeoPackage as a standard 2D gridded coverage (OGC
// GeoPackage "Tiled Gridded Coverage Data" extension, float32 TIFF tiles), so that GDAL, QGIS
// and `roadcross render` can read it (e.g. `gdalinfo GPKG:map.gpkg:terrain`, a hillshade with
// `gdaldem hillshade GPKG:map.gpkg:terrain hs.tif`). The runtime never reads it.
#pragma once

#include <string>

#include "roadcross/preprocess/terrain/terrain_grid.hpp"

namespace roadcross::preprocess {

/// Name of the coverage table.
inline constexpr const char* kTerrainTable = "terrain";

/// Adds `elevation` (UTM metres; NaN cells are stored as nodata -9999) to the GeoPackage at
/// `gpkg_path` as the gridded coverage table kTerrainTable. `last_change` (ISO 8601) is written as
/// its gpkg_contents.last_change so that the output stays byte-identical for identical inputs.
/// Throws OutputError when GDAL cannot write it. The grid is used up: its NaN cells are
/// overwritten with the nodata value and GDAL reads its memory in place (no copy).
void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                            const std::string& last_change);

}  // namespace roadcross::preprocess
