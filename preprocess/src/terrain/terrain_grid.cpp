#include "roadcross/preprocess/terrain/terrain_grid.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <memory>
#include <mutex>
#include <utility>

#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/gdal_module.hpp"
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

RasterElevation::RasterElevation(const std::string& path, const geo::UtmZone& zone)
    : backend_(gdal_module().open_raster(path, zone)) {}

RasterElevation::~RasterElevation() = default;

std::size_t RasterElevation::fill(Grid& grid) const {
  return backend_->fill(grid);
}

RasterElevation::PixelSize RasterElevation::pixel_size_at(double easting_m,
                                                          double northing_m) const {
  return backend_->pixel_size_at(easting_m, northing_m);
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
