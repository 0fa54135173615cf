#include "roadcross/preprocess/common/utm_grid.hpp"
#include "roadcross/preprocess/sight/obstacle_edge.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>

#include "roadcross/geo.hpp"

namespace rp = roadcross::preprocess;
namespace geo = roadcross::geo;

namespace {

double degrees(std::int32_t e7) {
  return static_cast<double>(e7) / 1e7;
}

struct Sample {
  double largest_error_m = 0.0;         ///< |interpolated - exact|, either coordinate
  int interpolated = 0, projected = 0;  ///< points the grid answered; the exact projection did
};

/// `points` random points in each of `boxes` random boxes of 0.05 x 0.05 degrees inside
/// latitudes lat_lo..lat_hi and within max_dlon_deg of zone's central meridian. Every point the
/// grid answers must be one geo::wgs84_to_utm projects (the others may be either).
Sample sample(geo::UtmZone zone, double lat_lo, double lat_hi, double max_dlon_deg, int boxes,
              int points, std::uint32_t seed) {
  std::mt19937 random(seed);
  const double central = 6.0 * zone.zone - 183.0;
  std::uniform_real_distribution<double> lat(lat_lo, lat_hi - 0.05);
  std::uniform_real_distribution<double> lon(central - max_dlon_deg, central + max_dlon_deg - 0.05);
  std::uniform_int_distribution<std::int32_t> offset(0, 500'000);
  Sample out;
  for (int b = 0; b < boxes; ++b) {
    const auto lon0 = static_cast<std::int32_t>(std::lround(lon(random) * 1e7));
    const auto lat0 = static_cast<std::int32_t>(std::lround(lat(random) * 1e7));
    const rp::UtmGrid grid(zone, lon0, lat0, lon0 + 500'000, lat0 + 500'000);
    for (int k = 0; k < points; ++k) {
      const std::int32_t x = lon0 + offset(random), y = lat0 + offset(random);
      double e = 0.0, n = 0.0;
      const bool interpolated = grid.project(x, y, e, n);
      geo::UtmPoint exact;
      try {
        exact = geo::wgs84_to_utm(degrees(y), degrees(x), zone);
      } catch (const std::exception&) {
        EXPECT_FALSE(interpolated) << "refused " << degrees(y) << ", " << degrees(x);
        continue;
      }
      ++out.projected;
      if (!interpolated) continue;
      ++out.interpolated;
      out.largest_error_m = std::max(
          {out.largest_error_m, std::abs(e - exact.easting_m), std::abs(n - exact.northing_m)});
    }
  }
  return out;
}

}  // namespace

// The error the class comment quotes, over the UTM domain: far inside kErrorBoundM.
TEST(UtmGrid, InterpolatesWithinAHundredthOfTheBoundEverywhereInAZone) {
  struct Band {
    geo::UtmZone zone;
    double lat_lo, lat_hi;
  };
  for (const Band& band :
       {Band{{32, true}, 0.0, 84.0}, Band{{33, true}, 45.0, 55.0}, Band{{1, false}, -80.0, 0.0},
        Band{{60, true}, 70.0, 84.0}, Band{{31, true}, -2.0, 2.0}}) {
    const Sample s = sample(band.zone, band.lat_lo, band.lat_hi, 6.4, 300, 40, 7);
    std::printf("zone %d: largest error %.3g m, %d of %d points interpolated\n", band.zone.zone,
                s.largest_error_m, s.interpolated, s.projected);
    RecordProperty("largest_error_m_zone_" + std::to_string(band.zone.zone),
                   std::to_string(s.largest_error_m));
    EXPECT_LT(s.largest_error_m, rp::UtmGrid::kErrorBoundM / 100) << "zone " << band.zone.zone;
    // Only the edges of what the exact projection accepts are left to it.
    EXPECT_GT(s.interpolated, 0.9 * s.projected) << "zone " << band.zone.zone;
  }
}

// At a node every weight but its own is 0 and its own is 1: the exact projection, bit for bit.
TEST(UtmGrid, IsTheExactProjectionAtItsNodes) {
  const geo::UtmZone zone{33, true};
  const rp::UtmGrid grid(zone, 144'000'000, 500'000'000, 145'000'000, 501'000'000);
  for (std::int32_t x = 144'000'000; x <= 145'000'000; x += rp::UtmGrid::kStepE7) {
    for (std::int32_t y = 500'000'000; y <= 501'000'000; y += rp::UtmGrid::kStepE7) {
      double e = 0.0, n = 0.0;
      ASSERT_TRUE(grid.project(x, y, e, n));
      const geo::UtmPoint exact = geo::wgs84_to_utm(degrees(y), degrees(x), zone);
      EXPECT_EQ(e, exact.easting_m);
      EXPECT_EQ(n, exact.northing_m);
    }
  }
}

// Its cells are the box's (and a node's width around it); elsewhere it answers false.
TEST(UtmGrid, AnswersOnlyInsideItsCells) {
  const rp::UtmGrid grid({33, true}, 144'000'000, 500'000'000, 144'500'000, 500'500'000);
  double e = 0.0, n = 0.0;
  EXPECT_TRUE(grid.project(144'000'000, 500'000'000, e, n));
  EXPECT_TRUE(grid.project(144'599'999, 500'599'999, e, n));  // the last cell's far corner
  EXPECT_FALSE(grid.project(144'600'000, 500'000'000, e, n));
  EXPECT_FALSE(grid.project(144'000'000, 500'600'000, e, n));
  EXPECT_FALSE(grid.project(143'999'999, 500'000'000, e, n));
  EXPECT_FALSE(grid.project(144'000'000, 499'999'999, e, n));
  EXPECT_FALSE(rp::UtmGrid().project(144'000'000, 500'000'000, e, n));
  EXPECT_EQ(rp::UtmGrid().nodes(), 0u);
}

// What geo::wgs84_to_utm refuses the grid leaves to it: beyond 84 degrees north, beyond 6.5
// degrees of the central meridian, an easting beyond GeographicLib's 0..1000 km.
TEST(UtmGrid, LeavesToTheExactProjectionWhatItRefuses) {
  const geo::UtmZone zone{33, true};  // central meridian 15 degrees
  double e = 0.0, n = 0.0;
  const rp::UtmGrid north(zone, 150'000'000, 837'000'000, 151'000'000, 839'900'000);
  EXPECT_TRUE(north.project(150'000'000, 839'000'000, e, n));
  // The cell [83.98, 83.99) needs nodes up to 84.00, which is projected; the next one 84.01.
  EXPECT_TRUE(north.project(150'000'000, 839'899'999, e, n));
  EXPECT_FALSE(north.project(150'000'000, 839'900'000, e, n));
  EXPECT_THROW(geo::wgs84_to_utm(84.0000001, 15.0, zone), std::invalid_argument);
  EXPECT_NO_THROW(geo::wgs84_to_utm(84.0, 15.0, zone));
  // At 60 degrees 6.5 degrees are 362 km: the easting is in range up to the 6.5 degrees.
  const rp::UtmGrid east(zone, 214'000'000, 600'000'000, 215'500'000, 601'000'000);
  EXPECT_TRUE(east.project(214'800'000, 600'500'000, e, n));
  EXPECT_TRUE(east.project(214'899'999, 600'500'000, e, n));   // nodes up to 21.50
  EXPECT_FALSE(east.project(214'900'000, 600'500'000, e, n));  // needs 21.51
  EXPECT_THROW(geo::wgs84_to_utm(60.05, 21.5000001, zone), std::invalid_argument);
  // At 10 degrees the easting passes 1000 km at 4.5 degrees from the meridian: GeographicLib
  // refuses it, and so does the grid, a hair before.
  const rp::UtmGrid low(zone, 190'000'000, 100'000'000, 200'000'000, 101'000'000);
  ASSERT_TRUE(low.project(190'000'000, 100'500'000, e, n));
  EXPECT_LT(e, 1'000'000.0);
  ASSERT_FALSE(low.project(199'000'000, 100'500'000, e, n));
  EXPECT_THROW(geo::wgs84_to_utm(10.05, 19.9, zone), std::runtime_error);
}

// A box too large for kMaxNodes gets no grid rather than a huge table.
TEST(UtmGrid, ABoxBeyondItsNodeLimitGetsNoGrid) {
  const rp::UtmGrid grid({33, true}, 90'000'000, 0, 210'000'000, 800'000'000);
  EXPECT_EQ(grid.nodes(), 0u);
  double e = 0.0, n = 0.0;
  EXPECT_FALSE(grid.project(150'000'000, 500'000'000, e, n));
}

// encode_certain answers only when every point within the error encodes as the point itself:
// checked at the error's corners and edges for UTM-sized coordinates, and it does answer for
// nearly all of them (the band it leaves is ~2 x error / unit wide).
TEST(UtmGrid, EncodeCertainIsEncodeForEveryPointWithinTheError) {
  const rp::VertexFrame frame =
      rp::VertexFrame::covering({480'000.0, 5'520'000.0}, {520'000.0, 5'560'000.0});
  std::mt19937 random(3);
  std::uniform_real_distribution<double> x(480'000.0, 520'000.0), y(5'520'000.0, 5'560'000.0);
  const double error_m = rp::UtmGrid::kErrorBoundM;
  int certain = 0;
  constexpr int kPoints = 200'000;
  for (int k = 0; k < kPoints; ++k) {
    const rp::PlanePoint p{x(random), y(random)};
    rp::FixedSlot slot{-1, -1};
    if (!frame.encode_certain(p, error_m, slot)) continue;
    ++certain;
    for (const double dx : {-error_m, -0.5 * error_m, 0.0, 0.5 * error_m, error_m}) {
      for (const double dy : {-error_m, 0.0, error_m}) {
        const rp::FixedSlot q = frame.encode({p.x + dx, p.y + dy});
        ASSERT_EQ(q.x, slot.x) << p.x << " " << dx;
        ASSERT_EQ(q.y, slot.y) << p.y << " " << dy;
      }
    }
  }
  EXPECT_GT(certain, 0.99 * kPoints);
  // A coordinate a hair from a half unit is left to the exact value.
  const double unit = frame.unit_m(), half = frame.origin().x + 1000.5 * unit;
  rp::FixedSlot slot{};
  EXPECT_FALSE(frame.encode_certain({half + 0.5 * error_m, 5'530'000.0}, error_m, slot));
  EXPECT_FALSE(frame.encode_certain({half - 0.5 * error_m, 5'530'000.0}, error_m, slot));
  EXPECT_TRUE(frame.encode_certain({half + 0.25 * unit, 5'530'000.0}, error_m, slot));
  EXPECT_EQ(slot.x, 1001);
  // Outside the frame: left to encode, which throws.
  EXPECT_FALSE(frame.encode_certain({frame.origin().x - 1.0, 5'530'000.0}, error_m, slot));
}
