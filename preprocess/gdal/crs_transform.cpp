// CrsTransform's GDAL/PROJ side: OGR coordinate transformations both ways.
#include <ogr_spatialref.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "module_parts.hpp"
#include "roadcross/preprocess/common/errors.hpp"

namespace roadcross::preprocess::gdal {

namespace {

void transform_in_place(OGRCoordinateTransformation& t, std::vector<double>& x,
                        std::vector<double>& y) {
  std::vector<int> ok(x.size(), 0);
  t.Transform(static_cast<int>(x.size()), x.data(), y.data(), nullptr, ok.data());
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i])) x[i] = y[i] = nan;
  }
}

class OgrCrsTransform final : public CrsTransformBackend {
 public:
  OgrCrsTransform(const std::string& crs, const geo::UtmZone& zone) {
    source_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    utm_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    OGRErr parsed = OGRERR_NONE;
    {
      const QuietGdal quiet;  // the ParameterError below says it for GDAL
      parsed = source_.SetFromUserInput(crs.c_str());
    }
    if (parsed != OGRERR_NONE) {
      throw ParameterError("--elevation-crs " + crs +
                           ": not a coordinate system GDAL/PROJ knows (use e.g. EPSG:5514)");
    }
    utm_.importFromEPSG(zone.epsg());
    forward_.reset(OGRCreateCoordinateTransformation(&source_, &utm_));
    inverse_.reset(OGRCreateCoordinateTransformation(&utm_, &source_));
    if (!forward_ || !inverse_) {
      throw ParameterError("no transformation from " + crs + " to UTM zone " +
                           std::to_string(zone.zone));
    }
  }

  void to_utm(std::vector<double>& x, std::vector<double>& y) const override {
    transform_in_place(*forward_, x, y);
  }
  void from_utm(std::vector<double>& x, std::vector<double>& y) const override {
    transform_in_place(*inverse_, x, y);
  }

 private:
  OGRSpatialReference source_, utm_;
  std::unique_ptr<OGRCoordinateTransformation> forward_, inverse_;
};

}  // namespace

std::unique_ptr<CrsTransformBackend> make_crs_transform(const std::string& crs,
                                                        const geo::UtmZone& zone) {
  return std::make_unique<OgrCrsTransform>(crs, zone);
}

}  // namespace roadcross::preprocess::gdal
