// libroadcross_gdal.so's entry point: the one GdalModule, handed out to a caller of the same
// interface and version (see common/gdal_module.hpp).
#include <cstring>

#include "module_parts.hpp"
#include "roadcross/version.hpp"

namespace roadcross::preprocess::gdal {
namespace {

class Module final : public GdalModule {
 public:
  std::unique_ptr<CrsTransformBackend> crs_transform(const std::string& crs,
                                                     const geo::UtmZone& zone) const override {
    return make_crs_transform(crs, zone);
  }
  std::unique_ptr<RasterBackend> open_raster(const std::string& path,
                                             const geo::UtmZone& zone) const override {
    return gdal::open_raster(path, zone);
  }
  void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                              const std::string& last_change) const override {
    gdal::write_terrain_coverage(gpkg_path, std::move(elevation), last_change);
  }
};

}  // namespace
}  // namespace roadcross::preprocess::gdal

extern "C" [[gnu::visibility("default")]] const roadcross::preprocess::GdalModule*
roadcross_gdal_module(int interface, const char* version) {
  namespace rp = roadcross::preprocess;
  if (interface != rp::kGdalModuleInterface || !version ||
      std::strcmp(version, roadcross::kVersion) != 0) {
    return nullptr;
  }
  static const rp::gdal::Module module;
  return &module;
}
