// GDAL is loaded only when a build has elevation input. Everything that calls GDAL or PROJ
// (rasters, CRS transformations, the terrain coverage written into the GeoPackage) lives in a
// separate shared module, libroadcross_gdal.so (preprocess/gdal/), opened at its first use.
// Linking libgdal and its ~100 libraries into roadcross-build cost ~65 ms of every start,
// with or without elevation (docs/performance.md, "GDAL loaded on demand").
//
// This header is the contract between the two: abstract classes the module implements, and
// the loader. Both sides are compiled from one tree: the module refuses a caller of another
// interface number or version, and the loader says so.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/terrain/terrain_grid.hpp"

namespace roadcross::preprocess {

/// A coordinate transformation between a user-given CRS and a UTM zone (see CrsTransform).
class CrsTransformBackend {
 public:
  virtual ~CrsTransformBackend() = default;
  /// In place, source CRS → UTM; points that cannot be transformed become NaN.
  virtual void to_utm(std::vector<double>& x, std::vector<double>& y) const = 0;
  /// In place, UTM → source CRS; failed points become NaN.
  virtual void from_utm(std::vector<double>& x, std::vector<double>& y) const = 0;
};

/// One open elevation raster (see RasterElevation). Not thread-safe.
class RasterBackend {
 public:
  virtual ~RasterBackend() = default;
  virtual std::size_t fill(Grid& grid) const = 0;
  virtual RasterElevation::PixelSize pixel_size_at(double easting_m, double northing_m) const = 0;
};

/// What libroadcross_gdal.so provides. Its functions throw the build's own errors
/// (InputError, ParameterError, OutputError), as the code did when it was linked in.
class GdalModule {
 public:
  /// Throws ParameterError when `crs` is not a CRS GDAL/PROJ knows.
  virtual std::unique_ptr<CrsTransformBackend> crs_transform(const std::string& crs,
                                                             const geo::UtmZone& zone) const = 0;
  /// Throws InputError when GDAL cannot read `path` or it has no band, CRS or geotransform.
  virtual std::unique_ptr<RasterBackend> open_raster(const std::string& path,
                                                     const geo::UtmZone& zone) const = 0;
  /// See write_terrain_coverage in output/terrain_coverage.hpp.
  virtual void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                                      const std::string& last_change) const = 0;

 protected:
  ~GdalModule() = default;  // the module's single instance lives as long as the process
};

/// The module's file name, looked for beside the executable.
inline constexpr const char* kGdalModuleFile = "libroadcross_gdal.so";
/// The module's one exported symbol: a `GdalModuleEntry`.
inline constexpr const char* kGdalModuleEntrySymbol = "roadcross_gdal_module";
/// Raised whenever GdalModule or the classes above change.
inline constexpr int kGdalModuleInterface = 1;
/// Returns the module, or null when `interface` or `version` (roadcross::kVersion) is not the
/// module's own.
using GdalModuleEntry = const GdalModule* (*)(int interface, const char* version);

/// The module, loaded at the first call (thread-safe). Looked for at $ROADCROSS_GDAL_MODULE
/// when that is set, otherwise beside the running executable, then where the installation puts
/// it (LIBDIR/roadcross, found relative to BINDIR), then where the build tree put it. Throws
/// std::runtime_error naming every place tried and why each failed; a later call tries again.
const GdalModule& gdal_module();

}  // namespace roadcross::preprocess
