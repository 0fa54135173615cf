// write_terrain_coverage's GDAL side: the grid copied from an in-memory raster into the
// GeoPackage's gridded coverage table by GDAL's GPKG driver.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "module_parts.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/output/terrain_coverage.hpp"

namespace roadcross::preprocess::gdal {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};

/// Sets a GDAL configuration option for the lifetime of the object, then restores it.
class ScopedConfig {
 public:
  ScopedConfig(const char* key, const std::string& value) : key_(key) {
    if (const char* old = CPLGetConfigOption(key, nullptr)) old_ = old, had_ = true;
    CPLSetThreadLocalConfigOption(key, value.c_str());
  }
  ~ScopedConfig() { CPLSetThreadLocalConfigOption(key_, had_ ? old_.c_str() : nullptr); }
  ScopedConfig(const ScopedConfig&) = delete;
  ScopedConfig& operator=(const ScopedConfig&) = delete;

 private:
  const char* key_;
  std::string old_;
  bool had_ = false;
};

/// Sets GDAL's (process-wide) block cache size for the lifetime of the object, then restores
/// it. Only for a stage where no other thread uses GDAL.
class ScopedCacheMax {
 public:
  explicit ScopedCacheMax(GIntBig bytes) : old_(GDALGetCacheMax64()) { GDALSetCacheMax64(bytes); }
  ~ScopedCacheMax() { GDALSetCacheMax64(old_); }
  ScopedCacheMax(const ScopedCacheMax&) = delete;
  ScopedCacheMax& operator=(const ScopedCacheMax&) = delete;

 private:
  GIntBig old_;
};

/// The block cache while the terrain grid is copied: a few rows of 256 x 256 float tiles.
constexpr GIntBig kCopyCacheBytes = 32 << 20;

/// The coverage's nodata value (GeoPackage coverages cannot record NaN).
constexpr double kNoDataM = -9999.0;

std::string gdal_message() {
  const char* message = CPLGetLastErrorMsg();
  return message && *message ? std::string(": ") + message : std::string();
}

}  // namespace

void write_terrain_coverage(const std::string& gpkg_path, Grid&& elevation,
                            const std::string& last_change) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!driver) throw OutputError("GDAL has no GeoPackage driver");
  // GDAL stamps gpkg_contents.last_change with "now" unless told otherwise.
  const ScopedConfig date("OGR_CURRENT_DATE", last_change);
  // As for the rest of the file (GeoPackageWriter): it is private until renamed into place, so
  // GDAL's connection needs no fsync and no rollback journal either (a failed build discards
  // the file).
  const ScopedConfig synchronous("OGR_SQLITE_SYNCHRONOUS", "OFF");
  const ScopedConfig journal("OGR_SQLITE_JOURNAL", "OFF");
  // GDAL's warnings (e.g. about the temporary file's extension) are not the user's business;
  // its failures reach the user through the OutputErrors below.
  CPLPushErrorHandler(CPLQuietErrorHandler);
  struct PopHandler {
    ~PopHandler() { CPLPopErrorHandler(); }
  } pop_handler;
  CPLErrorReset();
  CPLStringList options;
  options.SetNameValue("APPEND_SUBDATASET", "YES");
  options.SetNameValue("RASTER_TABLE", kTerrainTable);
  options.SetNameValue("RASTER_IDENTIFIER", "terrain elevation");
  options.SetNameValue("RASTER_DESCRIPTION",
                       "terrain grid of roadcross-build: elevation in metres, UTM, NaN = no data");
  options.SetNameValue("TILE_FORMAT", "TIFF");  // float32 gridded coverage
  options.SetNameValue("TILING_SCHEME", "CUSTOM");
  // An in-memory raster with everything set, copied into the GeoPackage the way gdal_translate
  // does it (the GPKG driver wants nodata, CRS and geotransform in a particular order). Its
  // band is the grid's own memory, NaN replaced by the nodata value in place, rows read north
  // to south through a negative line offset: a copy of the grid (up to 160 MB, in fresh pages)
  // cost more than the replacement.
  const GridSpec& s = elevation.spec;
  if (s.size() == 0) throw std::logic_error("write_terrain_coverage: an empty terrain grid");
  for (float& z : elevation.values) z = std::isnan(z) ? static_cast<float>(kNoDataM) : z;
  GDALDriver* memory = GetGDALDriverManager()->GetDriverByName("MEM");
  std::unique_ptr<GDALDataset, DatasetCloser> source(memory->Create(
      "", static_cast<int>(s.cols), static_cast<int>(s.rows), 0, GDT_Float32, nullptr));
  if (!source) throw OutputError("cannot set up the terrain grid's copy" + gdal_message());
  char north_row[64] = {};  // CPLPrintPointer does not terminate the string
  CPLPrintPointer(north_row, elevation.values.data() + (s.rows - 1) * s.cols, sizeof north_row - 1);
  CPLStringList band_options;
  band_options.SetNameValue("DATAPOINTER", north_row);
  band_options.SetNameValue("PIXELOFFSET", "4");
  band_options.SetNameValue("LINEOFFSET",
                            std::to_string(-static_cast<long long>(s.cols) * 4).c_str());
  if (source->AddBand(GDT_Float32, band_options.List()) != CE_None) {
    throw OutputError("cannot set up the terrain grid's copy" + gdal_message());
  }
  double geotransform[6] = {s.west_m, s.cell_m, 0.0, s.north_m(), 0.0, -s.cell_m};
  OGRSpatialReference utm;
  utm.importFromEPSG(s.zone.epsg());
  source->SetGeoTransform(geotransform);
  source->SetSpatialRef(&utm);
  source->GetRasterBand(1)->SetNoDataValue(kNoDataM);
  // GDAL's block cache (default 5 % of RAM) would hold every written tile until the final
  // flush: ~130 MB at 200x tiled Monaco, on top of the build's peak. Tiles are copied in
  // order, so a small cache writes them as they are done, in the same order.
  const ScopedCacheMax cache(kCopyCacheBytes);
  std::unique_ptr<GDALDataset, DatasetCloser> dataset(
      driver->CreateCopy(gpkg_path.c_str(), source.get(), FALSE, options.List(), nullptr, nullptr));
  if (!dataset) throw OutputError(gpkg_path + ": cannot add the terrain grid" + gdal_message());
  // GDAL 3.6 reports failures of the final flush only through its error state.
  CPLErrorReset();
  dataset.reset();
  if (CPLGetLastErrorType() >= CE_Failure) {
    throw OutputError(gpkg_path + ": cannot write the terrain grid" + gdal_message());
  }
}

}  // namespace roadcross::preprocess::gdal
