#include "roadcross/preprocess/common/utm_grid.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "roadcross/preprocess/common/parallel.hpp"

namespace roadcross::preprocess {

namespace {

/// floor(v / kStepE7) for any sign (integer division truncates towards zero).
std::int64_t grid_index(std::int64_t v) {
  const std::int64_t q = v / UtmGrid::kStepE7;
  return q * UtmGrid::kStepE7 > v ? q - 1 : q;
}

/// A grid coordinate in degrees, as osmium::Location converts its fixed point.
double degrees(std::int64_t index) {
  return static_cast<double>(index * UtmGrid::kStepE7) / 1e7;
}

/// The cubic Lagrange weights of the nodes at -1, 0, 1, 2 for a point at t in [0, 1).
void cubic_weights(double t, double w[4]) {
  const double a = t + 1.0, b = t, c = t - 1.0, d = t - 2.0;
  w[0] = -(b * c * d) / 6.0;
  w[1] = (a * c * d) / 2.0;
  w[2] = -(a * b * d) / 2.0;
  w[3] = (a * b * c) / 6.0;
}

}  // namespace

UtmGrid::UtmGrid(geo::UtmZone zone, std::int32_t min_lon_e7, std::int32_t min_lat_e7,
                 std::int32_t max_lon_e7, std::int32_t max_lat_e7) {
  zone_ = zone;
  central_meridian_e7_ = (std::int64_t{6} * zone.zone - 183) * 10'000'000;
  if (min_lon_e7 > max_lon_e7 || min_lat_e7 > max_lat_e7) return;
  // A point's cell [c, c + 1) needs nodes c - 1 .. c + 2.
  const std::int64_t first_column = grid_index(min_lon_e7) - 1;
  const std::int64_t first_row = grid_index(min_lat_e7) - 1;
  const std::int64_t columns = grid_index(max_lon_e7) + 2 - first_column + 1;
  const std::int64_t rows = grid_index(max_lat_e7) + 2 - first_row + 1;
  if (static_cast<double>(columns) * static_cast<double>(rows) > double(kMaxNodes)) return;
  first_column_ = first_column, first_row_ = first_row, columns_ = columns, rows_ = rows;
  nodes_.resize(static_cast<std::size_t>(columns * rows));
  parallel_for<NoState>(static_cast<std::size_t>(rows), [&](std::size_t row, NoState&) {
    const double lat_deg = degrees(first_row_ + static_cast<std::int64_t>(row));
    for (std::int64_t column = 0; column < columns_; ++column) {
      Node& node = nodes_[row * static_cast<std::size_t>(columns_) + std::size_t(column)];
      try {
        const geo::UtmPoint p = geo::wgs84_to_utm(lat_deg, degrees(first_column_ + column), zone);
        node = {p.easting_m, p.northing_m};
      } catch (const std::exception&) {  // (GeographicLib's own refusals are runtime_errors)
        node = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
      }
    }
  });
}

bool UtmGrid::project(std::int32_t lon_e7, std::int32_t lat_e7, double& easting_m,
                      double& northing_m) const {
  // geo::wgs84_to_utm's own refusals: outside latitudes -80..84 (exact on the fixed point:
  // both ends are whole degrees), further than 6.5 degrees from the central meridian (its
  // floating-point test, left to it within 1e-6 degrees of the limit, and across the
  // antimeridian).
  if (lat_e7 < -800'000'000 || lat_e7 > 840'000'000) return false;
  const std::int64_t from_central_e7 = std::int64_t{lon_e7} - central_meridian_e7_;
  if (from_central_e7 < -64'999'990 || from_central_e7 > 64'999'990) return false;
  const std::int64_t column = grid_index(lon_e7), row = grid_index(lat_e7);
  const std::int64_t c0 = column - 1 - first_column_, r0 = row - 1 - first_row_;
  if (c0 < 0 || r0 < 0 || c0 + 4 > columns_ || r0 + 4 > rows_) return false;
  double wx[4], wy[4];
  cubic_weights(double(lon_e7 - column * kStepE7) / double(kStepE7), wx);
  cubic_weights(double(lat_e7 - row * kStepE7) / double(kStepE7), wy);
  // Differences from the cell's own node (kilometres, not thousands of kilometres), so that the
  // sums round at the scale of the differences; they are exact (Sterbenz) for nodes within a
  // factor of two of it.
  const Node& base = nodes_[std::size_t((r0 + 1) * columns_ + c0 + 1)];
  double east = 0.0, north = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Node* node = &nodes_[std::size_t((r0 + k) * columns_ + c0)];
    double row_east = 0.0, row_north = 0.0;
    for (int i = 0; i < 4; ++i) {
      row_east += wx[i] * (node[i].easting_m - base.easting_m);
      row_north += wx[i] * (node[i].northing_m - base.northing_m);
    }
    east += wy[k] * row_east;
    north += wy[k] * row_north;
  }
  easting_m = base.easting_m + east;
  northing_m = base.northing_m + north;
  if (!(std::isfinite(easting_m) && std::isfinite(northing_m))) return false;
  // GeographicLib's range check (UTMUPS::CheckCoords without MGRS limits: the point's own
  // hemisphere's false northing, 100 km of slop): a point within the error of its limits is
  // left to the exact projection, which may refuse it.
  const bool north_of_equator = lat_e7 >= 0;
  const double own_northing_m = north_of_equator == zone_.northern
                                    ? northing_m
                                    : northing_m + (zone_.northern ? 10'000'000.0 : -10'000'000.0);
  const double min_northing_m = north_of_equator ? -9'100'000.0 : 900'000.0;
  const double max_northing_m = north_of_equator ? 9'600'000.0 : 19'600'000.0;
  return easting_m > kErrorBoundM && easting_m < 1'000'000.0 - kErrorBoundM &&
         own_northing_m > min_northing_m + kErrorBoundM &&
         own_northing_m < max_northing_m - kErrorBoundM;
}

}  // namespace roadcross::preprocess
