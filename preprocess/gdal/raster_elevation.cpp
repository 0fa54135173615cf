// RasterElevation's GDAL side: a raster's window read once per grid, sampled bilinearly at the
// grid's cell centres through a lattice of PROJ transformations.
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "module_parts.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace roadcross::preprocess::gdal {

namespace {

struct GdalDatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};

std::string gdal_message() {
  const char* message = CPLGetLastErrorMsg();
  return message && *message ? std::string(" (GDAL: ") + message + ")" : std::string();
}

/// Raster coordinates (fractional pixel column/row of pixel centres) of grid cell centres.
/// PROJ is called on a lattice of every kStep-th cell only and the rest interpolated linearly:
/// over kStep * cell_m (80 m by default) the transformation is linear to well below a millimetre.
/// A row is interpolated when it is needed, so a tile holds no per-cell coordinates.
class RasterLattice {
 public:
  RasterLattice(const GridSpec& spec, OGRCoordinateTransformation& utm_to_raster,
                const std::array<double, 6>& inverse_geotransform)
      : cols_((spec.cols + kStep - 1) / kStep + 1), px_(), py_() {
    const std::size_t rows = (spec.rows + kStep - 1) / kStep + 1;
    std::vector<double> x(cols_ * rows), y(x.size());
    for (std::size_t j = 0; j < rows; ++j) {
      for (std::size_t i = 0; i < cols_; ++i) {
        x[j * cols_ + i] = spec.centre_easting(i * kStep);
        y[j * cols_ + i] = spec.centre_northing(j * kStep);
      }
    }
    std::vector<int> ok(x.size(), 0);
    utm_to_raster.Transform(static_cast<int>(x.size()), x.data(), y.data(), nullptr, ok.data());
    const auto& g = inverse_geotransform;
    px_.resize(x.size()), py_.resize(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) {
      const bool good = ok[k] && std::isfinite(x[k]) && std::isfinite(y[k]);
      px_[k] = good ? g[0] + g[1] * x[k] + g[2] * y[k] - 0.5 : std::nan("");
      py_[k] = good ? g[3] + g[4] * x[k] + g[5] * y[k] - 0.5 : std::nan("");
    }
  }

  /// The raster coordinates of the centres of the cells of grid row `row` (NaN where PROJ
  /// failed), `px.size()` = the grid's columns. Lattice cell by lattice cell, so that the
  /// inner loop has fixed corners and vectorises; the same arithmetic as cell by cell.
  void row(std::size_t row, std::vector<float>& px, std::vector<float>& py) const {
    const std::size_t j = row / kStep;
    const double ty = double(row - j * kStep) / kStep;
    for (std::size_t i = 0; i * kStep < px.size(); ++i) {
      const std::size_t first = i * kStep, n = std::min(kStep, px.size() - first);
      interpolate(px_, j, i, ty, n, px.data() + first);
      interpolate(py_, j, i, ty, n, py.data() + first);
    }
  }

  /// The lattice's nodes, in any order (NaN where PROJ failed).
  std::size_t nodes() const { return px_.size(); }
  double node_px(std::size_t k) const { return px_[k]; }
  double node_py(std::size_t k) const { return py_[k]; }

 private:
  /// Bilinear between lattice nodes (i, j) .. (i + 1, j + 1) at the first n of the kStep
  /// cells of a row of lattice cell (i, j).
  void interpolate(const std::vector<double>& v, std::size_t j, std::size_t i, double ty,
                   std::size_t n, float* out) const {
    const double a = v[j * cols_ + i], b = v[j * cols_ + i + 1];
    const double c = v[(j + 1) * cols_ + i], d = v[(j + 1) * cols_ + i + 1];
    for (std::size_t k = 0; k < n; ++k) {
      const double tx = double(k) / kStep;
      out[k] =
          static_cast<float>((a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty);
    }
  }

  static constexpr std::size_t kStep = 16;
  std::size_t cols_;
  std::vector<double> px_, py_;  ///< at the lattice's nodes
};

/// The pixels [x0, x1] x [y0, y1] (inclusive) of the raster that a grid touches.
struct PixelWindow {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  bool empty() const { return x1 < x0 || y1 < y0; }
  int width() const { return x1 - x0 + 1; }
  int height() const { return y1 - y0 + 1; }
};

/// A window of a `width` x `height` raster that holds the bilinear neighbourhood of every cell,
/// from the lattice's nodes alone (no pass over the cells): a cell's raster coordinates are a
/// convex combination of four nodes, rounded once to float, so they lie within one float step
/// of the nodes' range; one pixel to spare each side covers that. (It may hold a few pixels
/// more than the cells need: the values filled do not depend on the window, see fill_cells.)
PixelWindow window_of(const RasterLattice& lattice, int width, int height) {
  double min_px = std::numeric_limits<double>::infinity(), max_px = -min_px;
  double min_py = min_px, max_py = max_px;
  for (std::size_t k = 0; k < lattice.nodes(); ++k) {
    const double px = lattice.node_px(k), py = lattice.node_py(k);
    if (std::isnan(px) || std::isnan(py)) continue;
    min_px = std::min(min_px, px), max_px = std::max(max_px, px);
    min_py = std::min(min_py, py), max_py = std::max(max_py, py);
  }
  PixelWindow w;
  if (!(min_px <= max_px && min_py <= max_py)) return w;  // PROJ failed everywhere
  // Clamped in double first: a node far outside the raster must not overflow the int.
  const auto clamp = [](double v, int hi) {
    return static_cast<int>(std::clamp(v, -1.0, double(hi)));
  };
  w.x0 = clamp(std::floor(min_px) - 1.0, width), w.x1 = clamp(std::floor(max_px) + 2.0, width);
  w.y0 = clamp(std::floor(min_py) - 1.0, height), w.y1 = clamp(std::floor(max_py) + 2.0, height);
  w.x0 = std::max(w.x0, 0), w.y0 = std::max(w.y0, 0);
  w.x1 = std::min(w.x1, width - 1), w.y1 = std::min(w.y1, height - 1);
  return w;
}

/// What fill_row needs of the raster: its window's pixels and its size.
struct PixelSource {
  const float* pixels;  ///< the window's, row-major, NaN = no data
  int window_x0, window_y0, window_w;
  int width, height;  ///< the raster's, both >= 2
};

/// Fills the NaN ones of `n` cells whose raster coordinates are px, py; returns how many were
/// filled and appends to `on_last` (as first_index + i) those filled on the raster's last
/// column or row. Its own function, so that the loop's values stay in registers (inlined into
/// the tile's fill they were spilled to the stack: 1.5x the instructions).
[[gnu::noinline]] std::size_t fill_row(const PixelSource& source, const float* px, const float* py,
                                       float* cells, std::size_t n, std::size_t first_index,
                                       std::vector<std::size_t>& on_last) {
  const float* const pixels = source.pixels;
  const std::ptrdiff_t window_w = source.window_w;
  const int x0 = source.window_x0, y0 = source.window_y0;
  const int last_c = source.width - 2, last_r = source.height - 2;
  const float last_x = float(source.width - 1), last_y = float(source.height - 1);
  std::size_t filled = 0;
  for (std::size_t col = 0; col < n; ++col) {
    const float x = px[col], y = py[col];
    // Also false for NaN coordinates.
    if (!(x >= 0.0f && y >= 0.0f && x <= last_x && y <= last_y) || !std::isnan(cells[col])) {
      continue;
    }
    const int c = std::min(static_cast<int>(x), last_c);
    const int r = std::min(static_cast<int>(y), last_r);
    const double tx = double(x) - c, ty = double(y) - r;
    const float* p = pixels + (r - y0) * window_w + (c - x0);
    const double z = (double(p[0]) * (1 - tx) + double(p[1]) * tx) * (1 - ty) +
                     (double(p[window_w]) * (1 - tx) + double(p[window_w + 1]) * tx) * ty;
    if (std::isnan(z)) continue;
    cells[col] = static_cast<float>(z);
    ++filled;
    if (x == last_x || y == last_y) on_last.push_back(first_index + col);
  }
  return filled;
}

/// Fills the NaN cells of `grid` bilinearly from `pixels` (those of `window`, a window of a
/// `width` x `height` raster holding every cell's neighbourhood; NaN = no data); returns the
/// cells filled. One pass over the cells, in absolute raster coordinates: the same values, bit
/// for bit, as the earlier two passes (the exact window of the cells first, then the fill
/// relative to it), whose checks reduce to these: a cell outside [0, width - 1] x [0, height -
/// 1] stays NaN, the pixel column is min(floor(px), width - 2), and nothing is filled when
/// the cells' smallest px is >= width - 1 (or py >= height - 1: a one-pixel window).
std::size_t fill_cells(Grid& grid, const RasterLattice& lattice, const PixelWindow& window,
                       const std::vector<float>& pixels, int width, int height) {
  if (width < 2 || height < 2) return 0;  // no pixel has a right or upper neighbour
  const PixelSource source{pixels.data(), window.x0, window.y0, window.width(), width, height};
  float min_px = std::numeric_limits<float>::infinity(), min_py = min_px;
  std::vector<std::size_t> on_last;  // filled cells at px == width - 1 or py == height - 1
  std::size_t filled = 0;
  const std::size_t cols = grid.spec.cols;
  std::vector<float> px(cols), py(cols);
  for (std::size_t row = 0; row < grid.spec.rows; ++row) {
    lattice.row(row, px, py);
    // NaN compares false: these minima skip the cells PROJ failed on (branch-free).
    float row_min_px = std::numeric_limits<float>::infinity(), row_min_py = row_min_px;
    for (std::size_t col = 0; col < cols; ++col) {
      row_min_px = px[col] < row_min_px ? px[col] : row_min_px;
      row_min_py = py[col] < row_min_py ? py[col] : row_min_py;
    }
    min_px = std::min(min_px, row_min_px), min_py = std::min(min_py, row_min_py);
    filled += fill_row(source, px.data(), py.data(), grid.values.data() + row * cols, cols,
                       row * cols, on_last);
  }
  if (min_px >= float(width - 1) || min_py >= float(height - 1)) {
    // Every cell lies on (or beyond) the raster's last column or row: the exact window is
    // one pixel wide and fills nothing. Only cells on that line were filled above.
    for (const std::size_t k : on_last) grid.values[k] = std::numeric_limits<float>::quiet_NaN();
    return 0;
  }
  return filled;
}

/// One GDAL dataset's first band, with the transformations between UTM and its CRS.
class GdalRaster final : public RasterBackend {
 public:
  GdalRaster(const std::string& path, const geo::UtmZone& zone);
  std::size_t fill(Grid& grid) const override;
  RasterElevation::PixelSize pixel_size_at(double easting_m, double northing_m) const override;

 private:
  [[noreturn]] void out_of_range(const PixelWindow& w, std::ptrdiff_t index, float value_m) const;
  std::vector<float> read(const PixelWindow& w) const;

  std::string path_;
  std::unique_ptr<GDALDataset, GdalDatasetCloser> dataset_;
  GDALRasterBand* band_ = nullptr;
  std::array<double, 6> geotransform_{}, inverse_geotransform_{};
  std::unique_ptr<OGRCoordinateTransformation> utm_to_raster_, raster_to_utm_;
  bool has_nodata_ = false;
  double nodata_ = 0.0;
  double scale_ = 1.0, offset_ = 0.0;  ///< 1 and 0 when the band has none
};

GdalRaster::GdalRaster(const std::string& path, const geo::UtmZone& zone) : path_(path) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  const QuietGdal quiet;
  CPLErrorReset();
  dataset_.reset(static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly)));
  if (!dataset_) throw InputError(path, "GDAL cannot read this elevation raster" + gdal_message());
  if (dataset_->GetRasterCount() < 1) throw InputError(path, "the raster has no band");
  const OGRSpatialReference* raster_crs = dataset_->GetSpatialRef();
  if (!raster_crs) {
    throw InputError(path,
                     "the raster has no coordinate system (georeference it, e.g. with "
                     "gdal_translate -a_srs)");
  }
  if (dataset_->GetGeoTransform(geotransform_.data()) != CE_None ||
      !GDALInvGeoTransform(geotransform_.data(), inverse_geotransform_.data())) {
    throw InputError(path, "the raster has no usable geotransform");
  }
  OGRSpatialReference utm, raster = *raster_crs;
  utm.importFromEPSG(zone.epsg());
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  raster.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  utm_to_raster_.reset(OGRCreateCoordinateTransformation(&utm, &raster));
  raster_to_utm_.reset(OGRCreateCoordinateTransformation(&raster, &utm));
  if (!utm_to_raster_ || !raster_to_utm_) {
    throw InputError(path, "no transformation between UTM and the raster's CRS");
  }
  band_ = dataset_->GetRasterBand(1);
  int has_nodata = 0, has_scale = 0, has_offset = 0;
  nodata_ = band_->GetNoDataValue(&has_nodata);
  has_nodata_ = has_nodata != 0;
  const double scale = band_->GetScale(&has_scale), offset = band_->GetOffset(&has_offset);
  // v * 1.0 + 0.0 is v: a band without scale or offset reads as before.
  scale_ = has_scale ? scale : 1.0;
  offset_ = has_offset ? offset : 0.0;
}

void GdalRaster::out_of_range(const PixelWindow& w, std::ptrdiff_t index, float value_m) const {
  const long long col = w.x0 + index % w.width(), row = w.y0 + index / w.width();
  throw InputError(path_, "pixel (column " + std::to_string(col) + ", row " + std::to_string(row) +
                              ") holds an altitude of " + format_number(value_m) + " m, outside [" +
                              format_number(kMinAltitudeM) + ", " + format_number(kMaxAltitudeM) +
                              "] m: a damaged raster, or its nodata value, scale or data type "
                              "is not set");
}

/// The window's pixels as elevations in metres (NaN: nodata); throws InputError at an
/// altitude outside [kMinAltitudeM, kMaxAltitudeM].
std::vector<float> GdalRaster::read(const PixelWindow& w) const {
  std::vector<float> pixels(static_cast<std::size_t>(w.width()) * w.height());
  if (band_->RasterIO(GF_Read, w.x0, w.y0, w.width(), w.height(), pixels.data(), w.width(),
                      w.height(), GDT_Float32, 0, 0) != CE_None) {
    throw InputError(path_, "cannot read the raster's pixels (truncated file?)" + gdal_message());
  }
  for (float& v : pixels) {
    if ((has_nodata_ &&
         (v == static_cast<float>(nodata_) || (std::isnan(nodata_) && std::isnan(v)))) ||
        !std::isfinite(v)) {
      v = std::numeric_limits<float>::quiet_NaN();
    } else {
      v = static_cast<float>(v * scale_ + offset_);
      if (!(v >= kMinAltitudeM && v <= kMaxAltitudeM)) out_of_range(w, &v - pixels.data(), v);
    }
  }
  return pixels;
}

std::size_t GdalRaster::fill(Grid& grid) const {
  const QuietGdal quiet;
  CPLErrorReset();
  const RasterLattice lattice(grid.spec, *utm_to_raster_, inverse_geotransform_);
  // Read only the window of the raster that the grid touches.
  const int width = dataset_->GetRasterXSize(), height = dataset_->GetRasterYSize();
  const PixelWindow window = window_of(lattice, width, height);
  if (window.empty()) return 0;  // the raster does not reach the grid
  return fill_cells(grid, lattice, window, read(window), width, height);
}

RasterElevation::PixelSize GdalRaster::pixel_size_at(double easting_m, double northing_m) const {
  const QuietGdal quiet;
  double x = easting_m, y = northing_m;
  RasterElevation::PixelSize size;
  if (!utm_to_raster_->Transform(1, &x, &y) || !std::isfinite(x) || !std::isfinite(y)) {
    return size;
  }
  const auto& ig = inverse_geotransform_;
  const double px = ig[0] + ig[1] * x + ig[2] * y, py = ig[3] + ig[4] * x + ig[5] * y;
  // The pixel's corner at (px, py) and its neighbours one column and one row on, in the
  // raster's CRS, then in UTM.
  const auto& g = geotransform_;
  std::array<double, 3> cx{}, cy{};
  for (int k = 0; k < 3; ++k) {
    const double c = px + (k == 1 ? 1.0 : 0.0), l = py + (k == 2 ? 1.0 : 0.0);
    cx[k] = g[0] + g[1] * c + g[2] * l;
    cy[k] = g[3] + g[4] * c + g[5] * l;
  }
  std::array<int, 3> ok{};
  if (!raster_to_utm_->Transform(3, cx.data(), cy.data(), nullptr, ok.data()) || !ok[0] || !ok[1] ||
      !ok[2]) {
    return size;
  }
  size.column_m = std::hypot(cx[1] - cx[0], cy[1] - cy[0]);
  size.row_m = std::hypot(cx[2] - cx[0], cy[2] - cy[0]);
  return size;
}

}  // namespace

std::unique_ptr<RasterBackend> open_raster(const std::string& path, const geo::UtmZone& zone) {
  return std::make_unique<GdalRaster>(path, zone);
}

}  // namespace roadcross::preprocess::gdal
