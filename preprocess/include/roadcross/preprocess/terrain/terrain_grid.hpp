// The terrain model: a regular elevation grid in the DB's UTM zone, filled from TINs of XYZ
// points (CGAL Delaunay, linear interpolation inside the hull) and from rasters (bilinear), with
// DEM voids filled from valid neighbours within a limit. Every later terrain measure (slope,
// TPI, landform) works on this grid, so 2D neighbourhood statistics are cheap.
#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace roadcross::preprocess {

/// Cell (col, row) has its centre at (west_m + (col + 0.5) * cell_m, south_m + (row + 0.5) *
/// cell_m) in UTM metres; row 0 is the southernmost.
struct GridSpec {
  geo::UtmZone zone;
  double west_m = 0.0, south_m = 0.0;
  double cell_m = 5.0;
  std::size_t cols = 0, rows = 0;

  double centre_easting(std::size_t col) const { return west_m + (double(col) + 0.5) * cell_m; }
  double centre_northing(std::size_t row) const { return south_m + (double(row) + 0.5) * cell_m; }
  double east_m() const { return west_m + double(cols) * cell_m; }
  double north_m() const { return south_m + double(rows) * cell_m; }
  std::size_t size() const { return cols * rows; }
};

/// The grid of `cell_m` cells covering the box [min_e, max_e] x [min_n, max_n] (UTM metres)
/// grown by `margin_m` on every side, its south-west corner on a multiple of `align_m` (default:
/// the cell size) so that the same roads give the same grid and overlapping grids share cells.
GridSpec grid_covering(const geo::UtmZone& zone, double min_e, double min_n, double max_e,
                       double max_n, double margin_m, double cell_m, double align_m = 0.0);

/// Bilinear between the four cell centres around (easting_m, northing_m), each value given by
/// `value(col, row)` (so that a grid computed only where it is sampled interpolates exactly as a
/// whole one); NaN when outside the grid or when any of the four is NaN.
template <typename Value>
double bilinear(const GridSpec& spec, double easting_m, double northing_m, const Value& value) {
  const double fx = (easting_m - spec.west_m) / spec.cell_m - 0.5;
  const double fy = (northing_m - spec.south_m) / spec.cell_m - 0.5;
  if (!(fx >= 0.0 && fy >= 0.0)) return std::numeric_limits<double>::quiet_NaN();
  auto col = static_cast<std::size_t>(fx), row = static_cast<std::size_t>(fy);
  // The last row/column centre itself is inside: interpolate in the cell below/left of it.
  if (col + 1 == spec.cols && fx == double(col)) --col;
  if (row + 1 == spec.rows && fy == double(row)) --row;
  if (col + 1 >= spec.cols || row + 1 >= spec.rows) return std::numeric_limits<double>::quiet_NaN();
  const double tx = fx - double(col), ty = fy - double(row);
  const double z00 = value(col, row), z10 = value(col + 1, row);
  const double z01 = value(col, row + 1), z11 = value(col + 1, row + 1);
  return (z00 * (1 - tx) + z10 * tx) * (1 - ty) + (z01 * (1 - tx) + z11 * tx) * ty;
}

/// A float raster over a GridSpec; NaN marks "no value".
struct Grid {
  GridSpec spec;
  std::vector<float> values;  ///< row-major, rows south to north

  explicit Grid(const GridSpec& s)
      : spec(s), values(s.size(), std::numeric_limits<float>::quiet_NaN()) {}
  /// The same grid in `storage`'s memory (e.g. an earlier tile's values): pages already in use
  /// cost neither a page fault nor the kernel's zeroing, which on this kind of machine cost
  /// ~10x more than writing them.
  Grid(const GridSpec& s, std::vector<float>&& storage) : spec(s), values(std::move(storage)) {
    values.assign(s.size(), std::numeric_limits<float>::quiet_NaN());
  }
  float at(std::size_t col, std::size_t row) const { return values[row * spec.cols + col]; }
  float& at(std::size_t col, std::size_t row) { return values[row * spec.cols + col]; }
  /// Bilinear between the four surrounding cell centres; NaN when outside the grid or when any
  /// of the four is NaN.
  double sample(double easting_m, double northing_m) const;
  std::size_t count_valid() const;
};

class RasterBackend;

/// Fills the NaN cells of `grid` from a raster file (any format and CRS GDAL knows; its nodata
/// value respected): bilinear between the raster's pixel centres, NaN next to nodata or outside.
/// Returns the number of cells filled. Throws InputError when GDAL cannot read the file or it
/// has no CRS.
std::size_t fill_from_raster(Grid& grid, const std::string& path);

/// A raster elevation file opened once for many grids (the terrain's tiles): the dataset, its
/// nodata value, scale and offset and the transformation from UTM to the raster's CRS are set
/// up here, not per tile. GDAL datasets are not thread-safe: one RasterElevation per thread.
/// Loads the GDAL module (throws std::runtime_error when it cannot).
class RasterElevation {
 public:
  /// Throws InputError when GDAL cannot read `path` or it has no band, CRS or geotransform.
  RasterElevation(const std::string& path, const geo::UtmZone& zone);
  ~RasterElevation();
  RasterElevation(const RasterElevation&) = delete;
  RasterElevation& operator=(const RasterElevation&) = delete;

  /// As fill_from_raster, on the calling thread; `grid` must be in the zone given above.
  std::size_t fill(Grid& grid) const;

  /// The raster's pixel at the UTM point (easting_m, northing_m), measured in UTM: the lengths
  /// of its two sides, metres (a pixel's column and row steps, each through the raster's
  /// geotransform and the CRS transformation; for a geographic raster the degrees become metres
  /// on the ellipsoid there). The point need not lie on the raster: the geotransform extends
  /// beyond it. NaN when the transformation fails there.
  struct PixelSize {
    double column_m = NAN, row_m = NAN;
  };
  PixelSize pixel_size_at(double easting_m, double northing_m) const;

 private:
  std::unique_ptr<RasterBackend> backend_;
};

/// Fills the NaN cells of `grid` by linear interpolation on the Delaunay triangulation of
/// `points` (UTM metres). Cells outside the convex hull, or in a triangle with an edge longer
/// than `max_edge_m` (a gap in the data), stay NaN. Returns the number of cells filled.
std::size_t fill_from_points(Grid& grid, const std::vector<ElevationPoint>& points_utm,
                             double max_edge_m);

/// Fills NaN cells that have valid cells within `max_distance_m` (DEM voids, e.g. SRTM along
/// a coast): repeated passes each giving a NaN cell the mean of its valid 8-neighbours, at
/// most max_distance_m / cell_m passes. Cells farther from data stay NaN. Returns cells filled.
/// `scratch` (optional): storage for the per-cell flags, kept for the next call.
std::size_t fill_voids(Grid& grid, double max_distance_m, std::vector<char>* scratch = nullptr);

}  // namespace roadcross::preprocess
