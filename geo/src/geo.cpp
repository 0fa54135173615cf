#include "roadcross/geo.hpp"
#include "roadcross/geo_box.hpp"

#include <GeographicLib/UTMUPS.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace roadcross::geo {
namespace {
std::string format_deg(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.7g", value);
  return text;
}
}  // namespace

double normalize_angle_rad(double angle_rad) noexcept {
  if (!std::isfinite(angle_rad)) return angle_rad;
  // remainder() gives [-pi, pi] exactly for representable inputs; fold -pi onto +pi.
  double r = remainder_fast(angle_rad, 2.0 * kPi);
  if (r <= -kPi) r += 2.0 * kPi;
  if (r > kPi) r -= 2.0 * kPi;
  return r;
}

double angle_difference_rad(double to_rad, double from_rad) noexcept {
  // Normalise each first so that large inputs lose no precision in the subtraction.
  return normalize_angle_rad(normalize_angle_rad(to_rad) - normalize_angle_rad(from_rad));
}

double ned_to_enu_yaw_rad(double yaw_ned_rad) noexcept {
  return normalize_angle_rad(kPi / 2.0 - yaw_ned_rad);
}

double enu_to_ned_yaw_rad(double yaw_enu_rad) noexcept {
  return normalize_angle_rad(kPi / 2.0 - yaw_enu_rad);
}

double deg_to_rad(double angle_deg) noexcept {
  return angle_deg * (kPi / 180.0);
}
double rad_to_deg(double angle_rad) noexcept {
  return angle_rad * (180.0 / kPi);
}

double yaw_rad_to_bearing_deg(double yaw_enu_rad) noexcept {
  double bearing = std::fmod(90.0 - rad_to_deg(yaw_enu_rad), 360.0);
  if (bearing < 0.0) bearing += 360.0;
  if (bearing >= 360.0) bearing -= 360.0;  // fmod of a tiny negative + 360 can round to 360
  return bearing;
}

double bearing_deg_to_yaw_rad(double bearing_deg) noexcept {
  return normalize_angle_rad(deg_to_rad(90.0 - std::fmod(bearing_deg, 360.0)));
}

double grid_yaw_rad(double d_east_m, double d_north_m) noexcept {
  return normalize_angle_rad(std::atan2(d_north_m, d_east_m));
}

bool is_valid_utm_lat_lon(double lat_deg, double lon_deg) noexcept {
  return std::isfinite(lat_deg) && std::isfinite(lon_deg) && lat_deg >= -80.0 && lat_deg <= 84.0 &&
         lon_deg >= -180.0 && lon_deg <= 180.0;
}

UtmZone standard_utm_zone(double lat_deg, double lon_deg) {
  if (!is_valid_utm_lat_lon(lat_deg, lon_deg)) {
    throw std::invalid_argument("position " + format_deg(lat_deg) + ", " + format_deg(lon_deg) +
                                " is outside the UTM domain");
  }
  return UtmZone{GeographicLib::UTMUPS::StandardZone(lat_deg, lon_deg), lat_deg >= 0.0};
}

UtmPoint wgs84_to_utm(double lat_deg, double lon_deg, UtmZone zone) {
  if (!is_valid_utm_lat_lon(lat_deg, lon_deg)) {
    throw std::invalid_argument("latitude " + format_deg(lat_deg) + ", longitude " +
                                format_deg(lon_deg) +
                                " is not a WGS84 position in the UTM domain (lat -80..84, lon "
                                "-180..180)");
  }
  // A zone is 6 degrees wide; beyond ~3.5 degrees outside it the scale error exceeds 0.3 %.
  const double central_meridian_deg = 6.0 * zone.zone - 183.0;
  double delta_lon = std::fmod(lon_deg - central_meridian_deg + 540.0, 360.0) - 180.0;
  if (std::abs(delta_lon) > 6.5) {
    throw std::invalid_argument("longitude " + format_deg(lon_deg) + " is too far from UTM zone " +
                                std::to_string(zone.zone) + " (central meridian " +
                                format_deg(central_meridian_deg) + ")");
  }
  UtmPoint out;
  int zone_out = 0;
  bool northern_out = true;
  double gamma_deg = 0.0, scale = 0.0;
  GeographicLib::UTMUPS::Forward(lat_deg, lon_deg, zone_out, northern_out, out.easting_m,
                                 out.northing_m, gamma_deg, scale, zone.zone);
  if (northern_out != zone.northern) {
    // Forward picks the hemisphere from the latitude; express in the requested one.
    out.northing_m += zone.northern ? -10'000'000.0 : 10'000'000.0;
  }
  // GeographicLib's gamma is the compass bearing of grid north (clockwise from true north);
  // a grid yaw becomes a true ENU yaw by subtracting it.
  out.convergence_rad = -deg_to_rad(gamma_deg);
  return out;
}

LatLon utm_to_wgs84(double easting_m, double northing_m, UtmZone zone) {
  LatLon out;
  GeographicLib::UTMUPS::Reverse(zone.zone, zone.northern, easting_m, northing_m, out.lat_deg,
                                 out.lon_deg);
  return out;
}

LatLonBox wgs84_box_of_utm_rectangle(UtmZone zone, double min_easting_m, double min_northing_m,
                                     double max_easting_m, double max_northing_m) {
  constexpr int kPointsPerSide = 128;
  constexpr double kMarginDeg = 1e-5;
  LatLonBox box{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  const auto take = [&](double easting_m, double northing_m) {
    const LatLon p = utm_to_wgs84(easting_m, northing_m, zone);
    box.min_lat_deg = std::min(box.min_lat_deg, p.lat_deg);
    box.max_lat_deg = std::max(box.max_lat_deg, p.lat_deg);
    box.min_lon_deg = std::min(box.min_lon_deg, p.lon_deg);
    box.max_lon_deg = std::max(box.max_lon_deg, p.lon_deg);
  };
  for (int i = 0; i <= kPointsPerSide; ++i) {
    const double t = static_cast<double>(i) / kPointsPerSide;
    const double e = min_easting_m + t * (max_easting_m - min_easting_m);
    const double n = min_northing_m + t * (max_northing_m - min_northing_m);
    take(e, min_northing_m);
    take(e, max_northing_m);
    take(min_easting_m, n);
    take(max_easting_m, n);
  }
  box.min_lat_deg -= kMarginDeg;
  box.min_lon_deg -= kMarginDeg;
  box.max_lat_deg += kMarginDeg;
  box.max_lon_deg += kMarginDeg;
  return box;
}

}  // namespace roadcross::geo
