#include "roadcross/preprocess/output/terrain_coverage.hpp"

#include <utility>

#include "roadcross/preprocess/common/gdal_module.hpp"

namespace roadcross::preprocess {

void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                            const std::string& last_change) {
  gdal_module().write_terrain_coverage(gpkg_path, std::move(elevation), last_change);
}

}  // namespace roadcross::preprocess
