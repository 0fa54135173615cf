// Angle and coordinate helpers, done once. Conventions (docs/architecture.md):
//  - yaw: ENU as in ROS REP-103, radians, 0 = east, counter-clockwise positive, in (-pi, pi];
//  - bearing_deg: compass, 0 = north, clockwise, degrees, in [0, 360); only at the edges;
//  - grid yaw in a UTM plane is atan2(dN, dE), a plane angle (never a great-circle formula).
#pragma once

#include <cmath>
#include <limits>

namespace roadcross::geo {

inline constexpr double kPi = 3.14159265358979323846;

/// std::remainder(x, y), bit for bit, without its library call where the quotient is 0 or 1
/// (an angle difference against 2 pi, nearly always; glibc's __remainder_finite was 2 % of the
/// build's CPU). For |x| <= y / 2 the quotient rounds to 0 (a tie to the even 0): x itself. For
/// y / 2 < |x| <= 2 y, |x| - y is exact (Sterbenz), and when it is below y / 2 the quotient
/// rounds to 1: x -/+ y (of either sign), exact, a zero with x's sign as IEEE 754 wants. Everything
/// else (ties at 3 y / 2, larger |x|, non-finite values, y not positive or too small for y / 2 to
/// be exact) goes to std::remainder.
inline double remainder_fast(double x, double y) noexcept {
  if (y >= 4.0 * std::numeric_limits<double>::min() && y <= std::numeric_limits<double>::max()) {
    const double half = 0.5 * y, ax = std::abs(x);
    if (ax <= half) return x;
    if (ax <= 2.0 * y) {
      const double r = ax - y;
      if (r < half) return x > 0.0 ? r : -r;  // r > -y / 2 as |x| > y / 2
    }
  }
  return std::remainder(x, y);
}

/// Normalises an angle to (-pi, pi]. `angle_rad`: any finite value, radians.
/// Exact at the edges: -pi maps to +pi, +pi stays +pi. Non-finite input is returned unchanged.
double normalize_angle_rad(double angle_rad) noexcept;

/// Signed smallest rotation from `from_rad` to `to_rad`, in (-pi, pi] radians.
/// Both in radians, any finite value. Positive = counter-clockwise.
double angle_difference_rad(double to_rad, double from_rad) noexcept;

/// Yaw NED (0 = north, clockwise) to ENU (0 = east, counter-clockwise): yaw_enu = pi/2 - yaw_ned.
/// Radians in, radians out in (-pi, pi].
double ned_to_enu_yaw_rad(double yaw_ned_rad) noexcept;
/// The inverse of ned_to_enu_yaw_rad (the mapping is its own inverse), radians in (-pi, pi].
double enu_to_ned_yaw_rad(double yaw_enu_rad) noexcept;

/// ENU yaw (radians) to a compass bearing in degrees, [0, 360).
double yaw_rad_to_bearing_deg(double yaw_enu_rad) noexcept;
/// Compass bearing (degrees, any finite value) to ENU yaw in (-pi, pi] radians.
double bearing_deg_to_yaw_rad(double bearing_deg) noexcept;

double deg_to_rad(double angle_deg) noexcept;
double rad_to_deg(double angle_rad) noexcept;

/// Plane yaw of the vector (d_east_m, d_north_m) in a projected (UTM) frame, (-pi, pi].
double grid_yaw_rad(double d_east_m, double d_north_m) noexcept;

struct UtmZone {
  int zone = 0;          ///< 1..60
  bool northern = true;  ///< hemisphere
  int epsg() const noexcept { return (northern ? 32600 : 32700) + zone; }
  // Written out rather than defaulted so that the public headers stay C++17: ROS1 code builds
  // as C++17 (its message headers use std::allocator<void>::rebind, gone in C++20).
  bool operator==(const UtmZone& other) const noexcept {
    return zone == other.zone && northern == other.northern;
  }
  bool operator!=(const UtmZone& other) const noexcept { return !(*this == other); }
};

struct UtmPoint {
  double easting_m = 0.0;
  double northing_m = 0.0;
  /// Rotation from the UTM grid frame to true ENU at this point, radians (counter-clockwise
  /// positive): true_yaw = grid_yaw + convergence_rad. It is minus GeographicLib's meridian
  /// convergence gamma; |value| < 0.06 rad inside a zone at mid latitudes.
  double convergence_rad = 0.0;
};

struct LatLon {
  double lat_deg = 0.0;  ///< WGS84 latitude, degrees, [-90, 90]
  double lon_deg = 0.0;  ///< WGS84 longitude, degrees, [-180, 180]
};

/// True when lat in [-80, 84] and lon in [-180, 180] (the UTM domain), both finite.
bool is_valid_utm_lat_lon(double lat_deg, double lon_deg) noexcept;

/// The standard UTM zone of a WGS84 position (GeographicLib's rules, including the Norway and
/// Svalbard exceptions). Precondition: is_valid_utm_lat_lon.
UtmZone standard_utm_zone(double lat_deg, double lon_deg);

/// Projects a WGS84 position into the given UTM zone (which need not be its standard zone:
/// a DB keeps one zone for all its points). Throws std::invalid_argument when the position is
/// outside the UTM domain or too far from the zone for the projection to be meaningful.
UtmPoint wgs84_to_utm(double lat_deg, double lon_deg, UtmZone zone);

/// Inverse of wgs84_to_utm.
LatLon utm_to_wgs84(double easting_m, double northing_m, UtmZone zone);

}  // namespace roadcross::geo
