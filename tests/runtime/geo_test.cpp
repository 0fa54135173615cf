// Angle and coordinate helpers. Reference coordinates come from GDAL/PROJ (gdaltransform),
// an implementation independent of GeographicLib:
//   echo "14.4 50.0" | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32633 -output_xy
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "roadcross/geo.hpp"

namespace geo = roadcross::geo;
using geo::kPi;

namespace {

TEST(NormalizeAngle, KeepsValuesInsideTheInterval) {
  EXPECT_DOUBLE_EQ(geo::normalize_angle_rad(0.0), 0.0);
  EXPECT_DOUBLE_EQ(geo::normalize_angle_rad(1.0), 1.0);
  EXPECT_DOUBLE_EQ(geo::normalize_angle_rad(-1.0), -1.0);
}

TEST(NormalizeAngle, PiEdgeIsHalfOpen) {
  // The interval is (-pi, pi]: +pi stays, -pi maps onto +pi.
  EXPECT_EQ(geo::normalize_angle_rad(kPi), kPi);
  EXPECT_EQ(geo::normalize_angle_rad(-kPi), kPi);
  // Just inside the edges stays where it is.
  const double below_pi = std::nextafter(kPi, 0.0);
  const double above_minus_pi = std::nextafter(-kPi, 0.0);
  EXPECT_EQ(geo::normalize_angle_rad(below_pi), below_pi);
  EXPECT_EQ(geo::normalize_angle_rad(above_minus_pi), above_minus_pi);
  // Just outside wraps to the other side.
  EXPECT_NEAR(geo::normalize_angle_rad(kPi + 1e-9), -kPi + 1e-9, 1e-15);
  EXPECT_NEAR(geo::normalize_angle_rad(-kPi - 1e-9), kPi - 1e-9, 1e-15);
}

TEST(NormalizeAngle, FoldsMultiplesOfTwoPi) {
  EXPECT_NEAR(geo::normalize_angle_rad(3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(geo::normalize_angle_rad(-3 * kPi), kPi, 1e-12);
  EXPECT_NEAR(geo::normalize_angle_rad(2 * kPi), 0.0, 1e-15);
  EXPECT_NEAR(geo::normalize_angle_rad(7.0 * 2 * kPi + 0.25), 0.25, 1e-12);
  EXPECT_NEAR(geo::normalize_angle_rad(-1000.0 * 2 * kPi - 0.25), -0.25, 1e-10);
  const double result = geo::normalize_angle_rad(1e6);
  EXPECT_GT(result, -kPi);
  EXPECT_LE(result, kPi);
  EXPECT_NEAR(std::cos(result), std::cos(1e6), 1e-9);
}

TEST(NormalizeAngle, PassesNonFiniteThrough) {
  EXPECT_TRUE(std::isnan(geo::normalize_angle_rad(std::numeric_limits<double>::quiet_NaN())));
}

namespace {
std::uint64_t bits_of(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}
}  // namespace

TEST(RemainderFast, BitIdenticalToStdRemainder) {
  // Bit patterns (a -0.0 against +0.0 and every NaN's are told apart), against glibc's
  // std::remainder: every x near a multiple and a half multiple of y, the ties among them.
  const double two_pi = 2.0 * std::acos(-1.0);
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double least = std::numeric_limits<double>::min();
  const double most = std::numeric_limits<double>::max();
  std::vector<double> ys = {two_pi,      2.0,         1.0,   3.0,  0.1,   1e-300,
                            4.0 * least, 3.0 * least, least, tiny, 1e300, most,
                            most / 2,    -two_pi,     0.0,   -0.0, inf,   nan};
  std::mt19937_64 random(27);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::size_t compared = 0;
  for (const double y : ys) {
    std::vector<double> xs = {0.0, -0.0, inf, -inf, nan, tiny, -tiny, most, -most};
    for (const double k : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 0.25, 0.75, 1.25, 1.75}) {
      for (const double sign : {1.0, -1.0}) {
        const double x = sign * k * y;  // the ties, when k * y is exact
        xs.push_back(x);
        double up = x, down = x;
        for (int step = 0; step < 4; ++step) {
          up = std::nextafter(up, inf);
          down = std::nextafter(down, -inf);
          xs.push_back(up);
          xs.push_back(down);
        }
      }
    }
    for (int i = 0; i < 20000; ++i) xs.push_back(3.0 * y * unit(random));
    for (int i = 0; i < 2000; ++i) xs.push_back(std::ldexp(unit(random), -40 + i % 80));
    for (const double x : xs) {
      ASSERT_EQ(bits_of(geo::remainder_fast(x, y)), bits_of(std::remainder(x, y)))
          << "x " << x << " y " << y;
      ++compared;
    }
  }
  EXPECT_GT(compared, 300000u);
  // The two cases of the fast path, by value.
  EXPECT_EQ(geo::remainder_fast(3.0, 2.0), -1.0);  // the tie 1.5: quotient 2, the even one
  EXPECT_EQ(geo::remainder_fast(2.9, 2.0), 0.8999999999999999);
  EXPECT_EQ(geo::remainder_fast(-1.0, 2.0), -1.0);  // the tie 0.5: quotient 0
  EXPECT_TRUE(std::signbit(geo::remainder_fast(-2.0, 2.0)));
}

TEST(AngleDifference, TakesTheShortWayAcrossTheSeam) {
  // From 179 deg to -179 deg is +2 deg (counter-clockwise through 180), not -358.
  EXPECT_NEAR(geo::angle_difference_rad(geo::deg_to_rad(-179), geo::deg_to_rad(179)),
              geo::deg_to_rad(2), 1e-12);
  EXPECT_NEAR(geo::angle_difference_rad(geo::deg_to_rad(179), geo::deg_to_rad(-179)),
              geo::deg_to_rad(-2), 1e-12);
  EXPECT_NEAR(geo::angle_difference_rad(0.5, 0.25), 0.25, 1e-15);
  // Opposite directions: exactly pi, never -pi.
  EXPECT_EQ(geo::angle_difference_rad(kPi / 2, -kPi / 2), kPi);
  EXPECT_EQ(geo::angle_difference_rad(-kPi / 2, kPi / 2), kPi);
  EXPECT_NEAR(geo::angle_difference_rad(10 * kPi + 0.1, -0.1), 0.2, 1e-12);
}

TEST(YawConventions, NedToEnuAndBack) {
  // NED 0 = north = ENU pi/2; NED pi/2 = east = ENU 0; NED pi = south = ENU -pi/2.
  EXPECT_NEAR(geo::ned_to_enu_yaw_rad(0.0), kPi / 2, 1e-15);
  EXPECT_NEAR(geo::ned_to_enu_yaw_rad(kPi / 2), 0.0, 1e-15);
  EXPECT_NEAR(geo::ned_to_enu_yaw_rad(kPi), -kPi / 2, 1e-15);
  EXPECT_NEAR(geo::ned_to_enu_yaw_rad(3 * kPi / 2), kPi, 1e-15);  // west
  for (double yaw = -3.0; yaw <= 3.0; yaw += 0.37) {
    EXPECT_NEAR(geo::ned_to_enu_yaw_rad(geo::enu_to_ned_yaw_rad(yaw)), yaw, 1e-12);
  }
}

TEST(YawConventions, BearingDegrees) {
  EXPECT_NEAR(geo::yaw_rad_to_bearing_deg(0.0), 90.0, 1e-12);        // east
  EXPECT_NEAR(geo::yaw_rad_to_bearing_deg(kPi / 2), 0.0, 1e-12);     // north
  EXPECT_NEAR(geo::yaw_rad_to_bearing_deg(-kPi / 2), 180.0, 1e-12);  // south
  EXPECT_NEAR(geo::yaw_rad_to_bearing_deg(kPi), 270.0, 1e-12);       // west
  EXPECT_NEAR(geo::yaw_rad_to_bearing_deg(-kPi), 270.0, 1e-12);
  // Just east of north: a bearing slightly above 0, never 360.
  const double b = geo::yaw_rad_to_bearing_deg(kPi / 2 + 1e-15);
  EXPECT_GE(b, 0.0);
  EXPECT_LT(b, 360.0);
  EXPECT_NEAR(geo::bearing_deg_to_yaw_rad(90.0), 0.0, 1e-12);
  EXPECT_NEAR(geo::bearing_deg_to_yaw_rad(0.0), kPi / 2, 1e-12);
  EXPECT_NEAR(geo::bearing_deg_to_yaw_rad(360.0), kPi / 2, 1e-12);
  EXPECT_NEAR(geo::bearing_deg_to_yaw_rad(270.0), kPi, 1e-12);
  EXPECT_NEAR(geo::bearing_deg_to_yaw_rad(-90.0), kPi, 1e-12);
}

TEST(GridYaw, IsThePlaneAngle) {
  EXPECT_NEAR(geo::grid_yaw_rad(1.0, 0.0), 0.0, 1e-15);
  EXPECT_NEAR(geo::grid_yaw_rad(0.0, 1.0), kPi / 2, 1e-15);
  EXPECT_NEAR(geo::grid_yaw_rad(-1.0, 0.0), kPi, 1e-15);
  EXPECT_NEAR(geo::grid_yaw_rad(0.0, -1.0), -kPi / 2, 1e-15);
  EXPECT_NEAR(geo::grid_yaw_rad(1.0, 1.0), kPi / 4, 1e-15);
}

TEST(Utm, StandardZones) {
  EXPECT_EQ(geo::standard_utm_zone(50.0755, 14.4186), (geo::UtmZone{33, true}));  // Prague
  EXPECT_EQ(geo::standard_utm_zone(43.73, 7.42), (geo::UtmZone{32, true}));       // Monaco
  EXPECT_EQ(geo::standard_utm_zone(-33.9, 18.4), (geo::UtmZone{34, false}));      // Cape Town
  // Norway exception: south-west Norway is in 32V although 4.5 E would be zone 31.
  EXPECT_EQ(geo::standard_utm_zone(60.0, 4.5).zone, 32);
  EXPECT_EQ((geo::UtmZone{33, true}).epsg(), 32633);
  EXPECT_EQ((geo::UtmZone{34, false}).epsg(), 32734);
}

TEST(Utm, ForwardAgreesWithGdal) {
  // gdaltransform -s_srs EPSG:4326 -t_srs EPSG:326zz / 327zz (PROJ), to a millimetre.
  struct Case {
    double lat, lon;
    geo::UtmZone zone;
    double easting, northing;
  };
  const Case cases[] = {
      {50.0, 14.4, {33, true}, 456999.890393961, 5538803.17916943},
      {43.73, 7.42, {32, true}, 372751.122818933, 4843098.23622307},
      {-33.9, 18.4, {34, false}, 259583.221660431, 6245888.04544077},
      // Forced into a neighbouring zone, as a DB that spans a zone edge does.
      {50.0, 11.9, {33, true}, 277850.815138674, 5543236.47174733},
      {50.0, 14.4, {32, true}, 886902.561959164, 5552616.48506873},
  };
  for (const Case& c : cases) {
    const geo::UtmPoint p = geo::wgs84_to_utm(c.lat, c.lon, c.zone);
    EXPECT_NEAR(p.easting_m, c.easting, 1e-3) << c.lat << " " << c.lon;
    EXPECT_NEAR(p.northing_m, c.northing, 1e-3) << c.lat << " " << c.lon;
  }
}

TEST(Utm, InverseAgreesWithGdalAndRoundTrips) {
  // echo "458803 5546712" | gdaltransform -s_srs EPSG:32633 -t_srs EPSG:4326
  const geo::LatLon ll = geo::utm_to_wgs84(458803.0, 5546712.0, {33, true});
  EXPECT_NEAR(ll.lat_deg, 50.0712556942788, 1e-9);
  EXPECT_NEAR(ll.lon_deg, 14.4243084011633, 1e-9);
  for (double lat = 49.0; lat <= 51.0; lat += 0.5) {
    for (double lon = 12.5; lon <= 17.5; lon += 1.25) {
      const geo::UtmPoint p = geo::wgs84_to_utm(lat, lon, {33, true});
      const geo::LatLon back = geo::utm_to_wgs84(p.easting_m, p.northing_m, {33, true});
      EXPECT_NEAR(back.lat_deg, lat, 1e-10);
      EXPECT_NEAR(back.lon_deg, lon, 1e-10);
    }
  }
}

TEST(Utm, ConvergenceTurnsGridYawIntoTrueYaw) {
  // True north at (50.0, 14.4) seen in the zone 33 grid, from two PROJ points 0.001 deg apart:
  //   14.4 50.0 -> 456999.890393961 5538803.17916943
  //   14.4 50.001 -> 457000.782347338 5538914.36269954
  const double grid_yaw_of_true_north =
      std::atan2(5538914.36269954 - 5538803.17916943, 457000.782347338 - 456999.890393961);
  const geo::UtmPoint p = geo::wgs84_to_utm(50.0, 14.4, {33, true});
  // true_yaw = grid_yaw + convergence, and true north's true yaw is pi/2.
  EXPECT_NEAR(grid_yaw_of_true_north + p.convergence_rad, kPi / 2, 1e-6);
  EXPECT_GT(p.convergence_rad, 0.0);  // west of the central meridian in the north
}

TEST(Utm, RejectsInvalidPositions) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(geo::wgs84_to_utm(nan, 14.0, {33, true}), std::invalid_argument);
  EXPECT_THROW(geo::wgs84_to_utm(50.0, nan, {33, true}), std::invalid_argument);
  EXPECT_THROW(geo::wgs84_to_utm(91.0, 14.0, {33, true}), std::invalid_argument);
  EXPECT_THROW(geo::wgs84_to_utm(85.0, 14.0, {33, true}), std::invalid_argument);  // UPS domain
  EXPECT_THROW(geo::wgs84_to_utm(50.0, 200.0, {33, true}), std::invalid_argument);
  EXPECT_THROW(geo::wgs84_to_utm(50.0, 40.0, {33, true}), std::invalid_argument);  // far zone
  EXPECT_THROW(geo::standard_utm_zone(nan, 0.0), std::invalid_argument);
  EXPECT_FALSE(geo::is_valid_utm_lat_lon(-81.0, 0.0));
  EXPECT_TRUE(geo::is_valid_utm_lat_lon(-80.0, -180.0));
}

}  // namespace
