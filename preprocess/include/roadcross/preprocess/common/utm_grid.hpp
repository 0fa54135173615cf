// UTM projections of many points of one area at a fraction of GeographicLib's cost, for the
// obstacles' fixed-point vertices (sight/obstacles.cpp), whose millions of building nodes made
// projection most of their stage: the exact projection (geo::wgs84_to_utm, the Krüger series
// with a dozen transcendental calls, ~3 500 instructions) on the nodes of a grid, and between
// them an interpolant (~100 instructions) that stays within kErrorBoundM of it. A caller that
// needs the exact projection's answer (a vertex rounded to the millimetre) takes this one only
// where every point within the bound gives the same answer, and asks geo::wgs84_to_utm
// otherwise.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "roadcross/geo.hpp"

namespace roadcross::preprocess {

/// geo::wgs84_to_utm by bicubic interpolation: exact projections on the nodes of a grid of
/// kStepE7 in longitude and latitude, and for a point the tensor product of the cubic Lagrange
/// polynomials through the 4 x 4 nodes around it. Positions are in OSM's fixed point, 1e-7
/// degrees (osmium::Location's x = longitude, y = latitude).
///
/// Error: the cubic interpolant's error is about h^4 / 24 times the projection's fourth
/// derivatives, ~R = 6.4e6 m for h = 1.75e-4 rad (0.01 degrees): ~1e-10 m. Measured against
/// geo::wgs84_to_utm over the whole UTM domain (tests/preprocess/utm_grid_test.cpp): below
/// 2e-9 m, the rounding of the sums included; kErrorBoundM claims 1e-6 m, 500 times that.
class UtmGrid {
 public:
  static constexpr std::int32_t kStepE7 = 100'000;  ///< 0.01 degrees between nodes
  static constexpr double kErrorBoundM = 1e-6;      ///< |interpolated - exact|, each coordinate
  /// A larger box gets no grid (every point then falls back): 32 MiB of nodes, 0.01 degrees
  /// apart, cover 16 x 13 degrees.
  static constexpr std::size_t kMaxNodes = std::size_t{1} << 21;

  /// No grid: project() is always false.
  UtmGrid() = default;

  /// The grid for `zone` whose cells cover longitudes min_lon_e7..max_lon_e7 and latitudes
  /// min_lat_e7..max_lat_e7 (1e-7 degrees, min <= max). Nodes the exact projection refuses
  /// (outside the UTM domain, too far from the zone) leave the cells that need them to the
  /// caller's exact projection. Projects its nodes on every core.
  UtmGrid(geo::UtmZone zone, std::int32_t min_lon_e7, std::int32_t min_lat_e7,
          std::int32_t max_lon_e7, std::int32_t max_lat_e7);

  /// The projection of (lon_e7, lat_e7) into the grid's zone within kErrorBoundM in each
  /// coordinate, for a point geo::wgs84_to_utm projects without an exception; false when the
  /// point is outside the grid's cells, a node it needs was refused, or the point is within
  /// the error of where geo::wgs84_to_utm or GeographicLib refuse a point (the values are then
  /// unspecified).
  bool project(std::int32_t lon_e7, std::int32_t lat_e7, double& easting_m,
               double& northing_m) const;

  /// Nodes held (0 without a grid).
  std::size_t nodes() const { return nodes_.size(); }

 private:
  struct Node {
    double easting_m, northing_m;  ///< NaN when refused
  };
  geo::UtmZone zone_;
  std::int64_t central_meridian_e7_ = 0;
  std::int64_t first_column_ = 0, first_row_ = 0;  ///< grid indices of nodes_[0]
  std::int64_t columns_ = 0, rows_ = 0;
  std::vector<Node> nodes_;  ///< row by row (latitude), each row by longitude
};

}  // namespace roadcross::preprocess
