#include "roadcross/preprocess/terrain/terrain_grid.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <memory>
#include <mutex>
#include <utility>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace roadcross::preprocess {

GridSpec grid_covering(const geo::UtmZone& zone, double min_e, double min_n, double max_e,
                       double max_n, double margin_m, double cell_m, double align_m) {
  if (!(align_m > 0.0)) align_m = cell_m;
  GridSpec spec;
  spec.zone = zone;
  spec.cell_m = cell_m;
  spec.west_m = std::floor((min_e - margin_m) / align_m) * align_m;
  spec.south_m = std::floor((min_n - margin_m) / align_m) * align_m;
  spec.cols = static_cast<std::size_t>(std::ceil((max_e + margin_m - spec.west_m) / cell_m));
  spec.rows = static_cast<std::size_t>(std::ceil((max_n + margin_m - spec.south_m) / cell_m));
  return spec;
}

double Grid::sample(double easting_m, double northing_m) const {
  return bilinear(spec, easting_m, northing_m,
                  [this](std::size_t col, std::size_t row) { return at(col, row); });
}

std::size_t Grid::count_valid() const {
  return static_cast<std::size_t>(
      std::count_if(values.begin(), values.end(), [](float v) { return !std::isnan(v); }));
}

namespace {

struct GdalDatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};

std::string gdal_message() {
  const char* message = CPLGetLastErrorMsg();
  return message && *message ? std::string(" (GDAL: ") + message + ")" : std::string();
}

/// Makes GDAL's messages go into our errors (which name the file), not raw onto stderr, for the
/// lifetime of the guard (GDAL's handler stack is per thread).
struct QuietGdal {
  QuietGdal() { CPLPushErrorHandler(CPLQuietErrorHandler); }
  ~QuietGdal() { CPLPopErrorHandler(); }
  QuietGdal(const QuietGdal&) = delete;
  QuietGdal& operator=(const QuietGdal&) = delete;
};

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

}  // namespace

struct RasterElevation::Impl {
  std::string path;
  std::unique_ptr<GDALDataset, GdalDatasetCloser> dataset;
  GDALRasterBand* band = nullptr;
  std::array<double, 6> geotransform{}, inverse_geotransform{};
  std::unique_ptr<OGRCoordinateTransformation> utm_to_raster, raster_to_utm;
  bool has_nodata = false;
  double nodata = 0.0;
  double scale = 1.0, offset = 0.0;  ///< 1 and 0 when the band has none

  [[noreturn]] void out_of_range(const PixelWindow& w, std::ptrdiff_t index, float value_m) const {
    const long long col = w.x0 + index % w.width(), row = w.y0 + index / w.width();
    throw InputError(path, "pixel (column " + std::to_string(col) + ", row " + std::to_string(row) +
                               ") holds an altitude of " + format_number(value_m) +
                               " m, outside [" + format_number(kMinAltitudeM) + ", " +
                               format_number(kMaxAltitudeM) +
                               "] m: a damaged raster, or its nodata value, scale or data type "
                               "is not set");
  }

  /// The window's pixels as elevations in metres (NaN: nodata); throws InputError at an
  /// altitude outside [kMinAltitudeM, kMaxAltitudeM].
  std::vector<float> read(const PixelWindow& w) const {
    std::vector<float> pixels(static_cast<std::size_t>(w.width()) * w.height());
    if (band->RasterIO(GF_Read, w.x0, w.y0, w.width(), w.height(), pixels.data(), w.width(),
                       w.height(), GDT_Float32, 0, 0) != CE_None) {
      throw InputError(path, "cannot read the raster's pixels (truncated file?)" + gdal_message());
    }
    for (float& v : pixels) {
      if ((has_nodata &&
           (v == static_cast<float>(nodata) || (std::isnan(nodata) && std::isnan(v)))) ||
          !std::isfinite(v)) {
        v = std::numeric_limits<float>::quiet_NaN();
      } else {
        v = static_cast<float>(v * scale + offset);
        if (!(v >= kMinAltitudeM && v <= kMaxAltitudeM)) out_of_range(w, &v - pixels.data(), v);
      }
    }
    return pixels;
  }
};

RasterElevation::RasterElevation(const std::string& path, const geo::UtmZone& zone)
    : impl_(std::make_unique<Impl>()) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  const QuietGdal quiet;
  CPLErrorReset();
  Impl& r = *impl_;
  r.path = path;
  r.dataset.reset(static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly)));
  if (!r.dataset) throw InputError(path, "GDAL cannot read this elevation raster" + gdal_message());
  if (r.dataset->GetRasterCount() < 1) throw InputError(path, "the raster has no band");
  const OGRSpatialReference* raster_crs = r.dataset->GetSpatialRef();
  if (!raster_crs) {
    throw InputError(path,
                     "the raster has no coordinate system (georeference it, e.g. with "
                     "gdal_translate -a_srs)");
  }
  std::array<double, 6>& geotransform = r.geotransform;
  if (r.dataset->GetGeoTransform(geotransform.data()) != CE_None ||
      !GDALInvGeoTransform(geotransform.data(), r.inverse_geotransform.data())) {
    throw InputError(path, "the raster has no usable geotransform");
  }
  OGRSpatialReference utm, raster = *raster_crs;
  utm.importFromEPSG(zone.epsg());
  utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  raster.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  r.utm_to_raster.reset(OGRCreateCoordinateTransformation(&utm, &raster));
  r.raster_to_utm.reset(OGRCreateCoordinateTransformation(&raster, &utm));
  if (!r.utm_to_raster || !r.raster_to_utm) {
    throw InputError(path, "no transformation between UTM and the raster's CRS");
  }
  r.band = r.dataset->GetRasterBand(1);
  int has_nodata = 0, has_scale = 0, has_offset = 0;
  r.nodata = r.band->GetNoDataValue(&has_nodata);
  r.has_nodata = has_nodata != 0;
  const double scale = r.band->GetScale(&has_scale), offset = r.band->GetOffset(&has_offset);
  // v * 1.0 + 0.0 is v: a band without scale or offset reads as before.
  r.scale = has_scale ? scale : 1.0;
  r.offset = has_offset ? offset : 0.0;
}

RasterElevation::~RasterElevation() = default;

std::size_t RasterElevation::fill(Grid& grid) const {
  const QuietGdal quiet;
  CPLErrorReset();
  const RasterLattice lattice(grid.spec, *impl_->utm_to_raster, impl_->inverse_geotransform);
  // Read only the window of the raster that the grid touches.
  const int width = impl_->dataset->GetRasterXSize(), height = impl_->dataset->GetRasterYSize();
  const PixelWindow window = window_of(lattice, width, height);
  if (window.empty()) return 0;  // the raster does not reach the grid
  return fill_cells(grid, lattice, window, impl_->read(window), width, height);
}

RasterElevation::PixelSize RasterElevation::pixel_size_at(double easting_m,
                                                          double northing_m) const {
  const QuietGdal quiet;
  const Impl& r = *impl_;
  double x = easting_m, y = northing_m;
  PixelSize size;
  if (!r.utm_to_raster->Transform(1, &x, &y) || !std::isfinite(x) || !std::isfinite(y)) {
    return size;
  }
  const auto& ig = r.inverse_geotransform;
  const double px = ig[0] + ig[1] * x + ig[2] * y, py = ig[3] + ig[4] * x + ig[5] * y;
  // The pixel's corner at (px, py) and its neighbours one column and one row on, in the
  // raster's CRS, then in UTM.
  const auto& g = r.geotransform;
  std::array<double, 3> cx{}, cy{};
  for (int k = 0; k < 3; ++k) {
    const double c = px + (k == 1 ? 1.0 : 0.0), l = py + (k == 2 ? 1.0 : 0.0);
    cx[k] = g[0] + g[1] * c + g[2] * l;
    cy[k] = g[3] + g[4] * c + g[5] * l;
  }
  std::array<int, 3> ok{};
  if (!r.raster_to_utm->Transform(3, cx.data(), cy.data(), nullptr, ok.data()) || !ok[0] ||
      !ok[1] || !ok[2]) {
    return size;
  }
  size.column_m = std::hypot(cx[1] - cx[0], cy[1] - cy[0]);
  size.row_m = std::hypot(cx[2] - cx[0], cy[2] - cy[0]);
  return size;
}

std::size_t fill_from_raster(Grid& grid, const std::string& path) {
  return RasterElevation(path, grid.spec.zone).fill(grid);
}

std::size_t fill_from_points(Grid& grid, const std::vector<ElevationPoint>& points_utm,
                             double max_edge_m) {
  using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
  using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<double, Kernel>;
  using DataStructure =
      CGAL::Triangulation_data_structure_2<VertexBase, CGAL::Triangulation_face_base_2<Kernel>>;
  using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, DataStructure>;
  using Point = Kernel::Point_2;

  // Only points that can influence a cell: inside the grid grown by one longest triangle edge.
  const GridSpec& s = grid.spec;
  std::vector<std::pair<Point, double>> inside;
  inside.reserve(points_utm.size());
  for (const ElevationPoint& p : points_utm) {
    if (p.x >= s.west_m - max_edge_m && p.x <= s.east_m() + max_edge_m &&
        p.y >= s.south_m - max_edge_m && p.y <= s.north_m() + max_edge_m) {
      inside.emplace_back(Point(p.x, p.y), p.z);
    }
  }
  if (inside.size() < 3) return 0;
  Delaunay tin;
  tin.insert(inside.begin(), inside.end());  // spatially sorted bulk insertion
  if (tin.dimension() < 2) return 0;         // all points on one line

  const double max_edge_sq = max_edge_m * max_edge_m;
  std::size_t filled = 0;
  Delaunay::Face_handle hint;
  for (std::size_t row = 0; row < s.rows; ++row) {
    for (std::size_t col = 0; col < s.cols; ++col) {
      float& cell = grid.at(col, row);
      if (!std::isnan(cell)) continue;
      const Point q(s.centre_easting(col), s.centre_northing(row));
      const Delaunay::Face_handle face = tin.locate(q, hint);  // walks from the last face
      hint = face;
      if (tin.is_infinite(face)) continue;  // outside the hull: no extrapolation
      const Point& a = face->vertex(0)->point();
      const Point& b = face->vertex(1)->point();
      const Point& c = face->vertex(2)->point();
      if (CGAL::squared_distance(a, b) > max_edge_sq ||
          CGAL::squared_distance(b, c) > max_edge_sq ||
          CGAL::squared_distance(c, a) > max_edge_sq) {
        continue;
      }
      // Barycentric coordinates of q in abc.
      const double det = (b.y() - c.y()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.y() - c.y());
      if (det == 0.0) continue;
      const double wa =
          ((b.y() - c.y()) * (q.x() - c.x()) + (c.x() - b.x()) * (q.y() - c.y())) / det;
      const double wb =
          ((c.y() - a.y()) * (q.x() - c.x()) + (a.x() - c.x()) * (q.y() - c.y())) / det;
      const double wc = 1.0 - wa - wb;
      cell = static_cast<float>(wa * face->vertex(0)->info() + wb * face->vertex(1)->info() +
                                wc * face->vertex(2)->info());
      ++filled;
    }
  }
  return filled;
}

std::size_t fill_voids(Grid& grid, double max_distance_m, std::vector<char>* scratch) {
  const GridSpec& s = grid.spec;
  const auto passes = static_cast<std::size_t>(std::floor(max_distance_m / s.cell_m));
  const auto neighbours = [&](std::size_t k, auto&& visit) {
    const std::size_t col = k % s.cols, row = k / s.cols;
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        if (dr == 0 && dc == 0) continue;
        if ((col == 0 && dc < 0) || (row == 0 && dr < 0) || (col + 1 == s.cols && dc > 0) ||
            (row + 1 == s.rows && dr > 0)) {
          continue;
        }
        visit(k + static_cast<std::size_t>(static_cast<std::ptrdiff_t>(dr) * s.cols + dc));
      }
    }
  };
  // The frontier: void cells next to a valid one.
  std::vector<std::size_t> frontier;
  std::vector<char> own_queued;
  std::vector<char>& queued = scratch ? *scratch : own_queued;
  queued.assign(grid.values.size(), 0);
  for (std::size_t k = 0; k < grid.values.size(); ++k) {
    if (!std::isnan(grid.values[k])) continue;
    bool next_to_data = false;
    neighbours(k, [&](std::size_t n) { next_to_data |= !std::isnan(grid.values[n]); });
    if (next_to_data) frontier.push_back(k), queued[k] = 1;
  }
  std::size_t filled = 0;
  std::vector<float> new_values;
  for (std::size_t pass = 0; pass < passes && !frontier.empty(); ++pass) {
    new_values.resize(frontier.size());
    for (std::size_t f = 0; f < frontier.size(); ++f) {
      double sum = 0.0;
      int count = 0;
      neighbours(frontier[f], [&](std::size_t n) {
        if (!std::isnan(grid.values[n])) sum += grid.values[n], ++count;
      });
      new_values[f] = static_cast<float>(sum / count);
    }
    for (std::size_t f = 0; f < frontier.size(); ++f) grid.values[frontier[f]] = new_values[f];
    filled += frontier.size();
    std::vector<std::size_t> next;
    for (const std::size_t k : frontier) {
      neighbours(k, [&](std::size_t n) {
        if (std::isnan(grid.values[n]) && !queued[n]) next.push_back(n), queued[n] = 1;
      });
    }
    frontier = std::move(next);
  }
  return filled;
}

}  // namespace roadcross::preprocess
