#include "hillshade.hpp"

#include <gdal_priv.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

namespace roadcross::viz {

namespace {

constexpr double kSunAzimuthDeg = 315.0;  // from the north-west, as cartographers light maps
constexpr double kSunAltitudeDeg = 45.0;
constexpr double kZFactor = 2.0;  // city relief is gentle: exaggerate so streets' hills show

struct Window {
  int col = 0, row = 0, cols = 0, rows = 0;
};

// The grid cells covering `area` plus one cell of margin for Horn's 3x3 kernel.
std::optional<Window> window_of(const double gt[6], int width, int height, const UtmBox& area) {
  const double cell_e = gt[1], cell_n = -gt[5];
  const int c0 = std::max(0, static_cast<int>(std::floor((area.min_e_m - gt[0]) / cell_e)) - 1);
  const int c1 = std::min(width, static_cast<int>(std::ceil((area.max_e_m - gt[0]) / cell_e)) + 1);
  const int r0 = std::max(0, static_cast<int>(std::floor((gt[3] - area.max_n_m) / cell_n)) - 1);
  const int r1 = std::min(height, static_cast<int>(std::ceil((gt[3] - area.min_n_m) / cell_n)) + 1);
  if (c1 - c0 < 3 || r1 - r0 < 3) return std::nullopt;
  return Window{c0, r0, c1 - c0, r1 - r0};
}

// 0..1 brightness of Horn's hillshade at interior cell (x, y); negative when a neighbour is
// missing.
double shade_at(const std::vector<float>& z, int w, int x, int y, float nodata, double cell_m) {
  auto at = [&](int dx, int dy) -> double {
    return z[static_cast<std::size_t>(y + dy) * static_cast<std::size_t>(w) +
             static_cast<std::size_t>(x + dx)];
  };
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (at(dx, dy) == nodata || std::isnan(at(dx, dy))) return -1.0;
  const double a = at(-1, -1), b = at(0, -1), c = at(1, -1), d = at(-1, 0), f = at(1, 0),
               g = at(-1, 1), h = at(0, 1), i = at(1, 1);
  const double dzdx = ((c + 2 * f + i) - (a + 2 * d + g)) / (8 * cell_m);
  const double dzdy = ((g + 2 * h + i) - (a + 2 * b + c)) / (8 * cell_m);
  const double slope = std::atan(kZFactor * std::hypot(dzdx, dzdy));
  const double aspect = std::atan2(dzdy, -dzdx);
  const double zenith = (90.0 - kSunAltitudeDeg) * std::numbers::pi / 180.0;
  const double azimuth = (360.0 - kSunAzimuthDeg + 90.0) * std::numbers::pi / 180.0;
  const double v = std::cos(zenith) * std::cos(slope) +
                   std::sin(zenith) * std::sin(slope) * std::cos(azimuth - aspect);
  return std::clamp(v, 0.0, 1.0);
}

}  // namespace

std::optional<ShadeImage> hillshade(const std::string& db_path, const UtmBox& area) {
  GDALAllRegister();
  const std::string name = "GPKG:" + db_path + ":" + kTerrainTable;
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY,
                                                    nullptr, nullptr, nullptr));
  if (!ds) throw std::runtime_error("cannot read the terrain coverage " + name);
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None || gt[2] != 0.0 || gt[4] != 0.0)
    throw std::runtime_error(name + ": not a north-up grid");
  const auto window = window_of(gt, ds->GetRasterXSize(), ds->GetRasterYSize(), area);
  if (!window) return std::nullopt;
  GDALRasterBand* band = ds->GetRasterBand(1);
  int has_nodata = 0;
  const auto nodata = static_cast<float>(band->GetNoDataValue(&has_nodata));
  std::vector<float> z(static_cast<std::size_t>(window->cols) *
                       static_cast<std::size_t>(window->rows));
  if (band->RasterIO(GF_Read, window->col, window->row, window->cols, window->rows, z.data(),
                     window->cols, window->rows, GDT_Float32, 0, 0) != CE_None) {
    throw std::runtime_error(name + ": cannot read the elevation cells");
  }
  ShadeImage image;
  image.width = window->cols;
  image.height = window->rows;
  image.cell_m = gt[1];
  image.west_m = gt[0] + window->col * gt[1];
  image.north_m = gt[3] + window->row * gt[5];
  image.argb.assign(z.size(), 0u);
  for (int y = 1; y + 1 < image.height; ++y) {
    for (int x = 1; x + 1 < image.width; ++x) {
      const double v = shade_at(z, image.width, x, y, has_nodata ? nodata : NAN, image.cell_m);
      if (v < 0.0) continue;
      const auto grey = static_cast<std::uint32_t>(std::lround(v * 255.0));
      image.argb[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                 static_cast<std::size_t>(x)] = 0xff000000u | (grey << 16) | (grey << 8) | grey;
    }
  }
  return image;
}

namespace {

double mercator_y(double lat_deg) {
  return std::log(std::tan(std::numbers::pi / 4 + lat_deg * std::numbers::pi / 360));
}

double mercator_lat_deg(double y) {
  return (2 * std::atan(std::exp(y)) - std::numbers::pi / 2) * 180 / std::numbers::pi;
}

// UTM of output pixel centres, exact on a coarse lattice and bilinear in between: the
// projection bends far too little over a few pixels for the difference to show.
class PixelToUtm {
 public:
  static constexpr int kStep = 16;
  PixelToUtm(const MercatorShade& m, int width, int height, const geo::UtmZone& zone)
      : cols_(width / kStep + 2), rows_(height / kStep + 2) {
    const double y_top = mercator_y(m.north_lat_deg), y_bottom = mercator_y(m.south_lat_deg);
    for (int r = 0; r < rows_; ++r) {
      for (int c = 0; c < cols_; ++c) {
        const double px = c * kStep + 0.5, py = r * kStep + 0.5;
        const double lon = m.west_lon_deg + px / width * (m.east_lon_deg - m.west_lon_deg);
        const double lat = mercator_lat_deg(y_top - py / height * (y_top - y_bottom));
        const geo::UtmPoint p = geo::wgs84_to_utm(lat, lon, zone);
        lattice_.push_back({p.easting_m, p.northing_m});
      }
    }
  }
  schema::PlanePoint at(int x, int y) const {
    const int c = x / kStep, r = y / kStep;
    const double fx = (x % kStep) / double(kStep), fy = (y % kStep) / double(kStep);
    auto node = [&](int dc, int dr) { return lattice_[std::size_t((r + dr) * cols_ + c + dc)]; };
    auto mix = [](double a, double b, double t) { return a + (b - a) * t; };
    const auto a = node(0, 0), b = node(1, 0), d = node(0, 1), e = node(1, 1);
    return {mix(mix(a.x, b.x, fx), mix(d.x, e.x, fx), fy),
            mix(mix(a.y, b.y, fx), mix(d.y, e.y, fx), fy)};
  }

 private:
  int cols_, rows_;
  std::vector<schema::PlanePoint> lattice_;
};

}  // namespace

std::optional<MercatorShade> mercator_hillshade(const std::string& db_path, const UtmBox& area,
                                                const geo::UtmZone& zone, int max_width_px) {
  const std::optional<ShadeImage> shade = hillshade(db_path, area);
  if (!shade) return std::nullopt;
  MercatorShade m;
  m.west_lon_deg = m.south_lat_deg = INFINITY;
  m.east_lon_deg = m.north_lat_deg = -INFINITY;
  for (double e : {area.min_e_m, area.max_e_m}) {
    for (double n : {area.min_n_m, area.max_n_m}) {
      const geo::LatLon p = geo::utm_to_wgs84(e, n, zone);
      m.west_lon_deg = std::min(m.west_lon_deg, p.lon_deg);
      m.east_lon_deg = std::max(m.east_lon_deg, p.lon_deg);
      m.south_lat_deg = std::min(m.south_lat_deg, p.lat_deg);
      m.north_lat_deg = std::max(m.north_lat_deg, p.lat_deg);
    }
  }
  const int width = std::clamp(static_cast<int>(area.width_m() / shade->cell_m), 2, max_width_px);
  const double aspect = (mercator_y(m.north_lat_deg) - mercator_y(m.south_lat_deg)) /
                        ((m.east_lon_deg - m.west_lon_deg) * std::numbers::pi / 180);
  const int height = std::max(2, static_cast<int>(std::lround(width * aspect)));
  m.image.width = width;
  m.image.height = height;
  m.image.argb.assign(std::size_t(width) * std::size_t(height), 0u);
  const PixelToUtm to_utm(m, width, height, zone);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const schema::PlanePoint p = to_utm.at(x, y);
      const auto col = static_cast<long>(std::floor((p.x - shade->west_m) / shade->cell_m));
      const auto row = static_cast<long>(std::floor((shade->north_m - p.y) / shade->cell_m));
      if (col < 0 || row < 0 || col >= shade->width || row >= shade->height) continue;
      m.image.argb[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
          shade->argb[std::size_t(row) * std::size_t(shade->width) + std::size_t(col)];
    }
  }
  return m;
}

}  // namespace roadcross::viz
