// The terrain model on analytic surfaces whose slope, TPI and landform are known by hand:
// a plane, a Gaussian hill, a V valley; TIN and raster sampling; void filling; and the whole
// build on a road over a hill, from XYZ points and from a GeoTIFF.
#include <gdal_priv.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"
#include "roadcross/preprocess/terrain/terrain_grid.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace geo = roadcross::geo;
using roadcross::testing::TempDir;

namespace {

constexpr double kPi = std::numbers::pi;
const geo::UtmZone kZone{33, true};
// A point on zone 33's central meridian (lon 15 E), where grid north is true north.
constexpr double kE0 = 500000.0, kN0 = 5540000.0;

using Surface = std::function<double(double e, double n)>;

/// A grid of `half_m` around (kE0, kN0) with the surface sampled at cell centres.
rp::Grid grid_of(const Surface& z, double half_m, double cell_m = 5.0) {
  rp::Grid grid(rp::grid_covering(kZone, kE0 - half_m, kN0 - half_m, kE0 + half_m, kN0 + half_m,
                                  0.0, cell_m));
  for (std::size_t row = 0; row < grid.spec.rows; ++row) {
    for (std::size_t col = 0; col < grid.spec.cols; ++col) {
      grid.at(col, row) =
          static_cast<float>(z(grid.spec.centre_easting(col), grid.spec.centre_northing(row)));
    }
  }
  return grid;
}

double gaussian_hill(double e, double n) {  // 50 m high, sigma 100 m, centred on (kE0, kN0)
  const double r2 = (e - kE0) * (e - kE0) + (n - kN0) * (n - kN0);
  return 300.0 + 50.0 * std::exp(-r2 / (2 * 100.0 * 100.0));
}

double v_valley(double e, double) {
  return 300.0 + 0.2 * std::abs(e - kE0);
}

/// Mean of exp(-r^2 / (2 s^2)) over the annulus r1 < r <= r2 (area-weighted), by hand:
/// s^2 (exp(-r1^2/2s^2) - exp(-r2^2/2s^2)) / ((r2^2 - r1^2) / 2).
double gaussian_annulus_mean(double s, double r1, double r2) {
  return s * s * (std::exp(-r1 * r1 / (2 * s * s)) - std::exp(-r2 * r2 / (2 * s * s))) /
         ((r2 * r2 - r1 * r1) / 2);
}

/// Mean of |x| over the annulus r1 < r <= r2: (2/pi) times the mean radius
/// (2/3)(r2^3 - r1^3)/(r2^2 - r1^2).
double abs_x_annulus_mean(double r1, double r2) {
  return 2.0 / kPi * (2.0 / 3.0) * (r2 * r2 * r2 - r1 * r1 * r1) / (r2 * r2 - r1 * r1);
}

rp::Landform landform_at(const rp::TerrainModel& m, const rp::TerrainParameters& p, double e,
                         double n) {
  return rp::classify_landform((m.tpi_small.sample(e, n) - m.small_stats.mean) / m.small_sd_used,
                               (m.tpi_large.sample(e, n) - m.large_stats.mean) / m.large_sd_used,
                               m.slope.sample(e, n), p);
}

}  // namespace

TEST(Terrain, PlaneHasItsSlopeAndZeroTpi) {
  const rp::TerrainParameters p;
  // z rises 10 m per 100 m eastwards: slope atan(0.1) = 5.7106 degrees.
  const rp::TerrainModel m = rp::analyse_terrain(
      grid_of([](double e, double) { return 200.0 + 0.1 * (e - kE0); }, 700.0), p);
  EXPECT_NEAR(m.slope.sample(kE0 + 2.5, kN0 + 2.5), std::atan(0.1) * 180.0 / kPi, 1e-3);
  EXPECT_NEAR(m.tpi_small.sample(kE0 + 2.5, kN0 + 2.5), 0.0, 1e-3);
  EXPECT_NEAR(m.tpi_large.sample(kE0 + 2.5, kN0 + 2.5), 0.0, 1e-3);
  EXPECT_EQ(landform_at(m, p, kE0, kN0), rp::Landform::open_slope);  // 5.7 > 5 degrees
  // Half as steep: 2.86 degrees, plains.
  const rp::TerrainModel gentle = rp::analyse_terrain(
      grid_of([](double e, double) { return 200.0 + 0.05 * (e - kE0); }, 700.0), p);
  EXPECT_EQ(landform_at(gentle, p, kE0, kN0), rp::Landform::plains);
  // The grid's edge (no full 3x3 neighbourhood) has no slope.
  EXPECT_TRUE(std::isnan(m.slope.at(0, 10)));
}

TEST(Terrain, GaussianHillTopIsAMountainTopAndItsFootIsNot) {
  const rp::TerrainParameters p;
  const rp::TerrainModel m = rp::analyse_terrain(grid_of(gaussian_hill, 1000.0), p);
  // The top is on a cell centre; the annulus means by hand (continuous annulus; the cell
  // approximation differs by a few centimetres).
  const double e = kE0 + 2.5, n = kN0 + 2.5;
  ASSERT_NEAR(m.elevation.sample(e, n), gaussian_hill(e, n), 1e-4);
  const double top = 50.0;
  EXPECT_NEAR(m.tpi_small.at(200, 200), top * (1 - gaussian_annulus_mean(100, 10, 50)), 0.1);
  EXPECT_NEAR(m.tpi_large.at(200, 200), top * (1 - gaussian_annulus_mean(100, 100, 300)), 0.3);
  EXPECT_EQ(landform_at(m, p, e, n), rp::Landform::mountain_top);
  EXPECT_TRUE(rp::is_crest_or_dip(landform_at(m, p, e, n)));
  // At the foot, 400 m out, the ground is flat and lower than the hill beside it.
  const rp::Landform foot = landform_at(m, p, kE0 + 400.0, kN0);
  EXPECT_FALSE(rp::is_crest_or_dip(foot)) << rp::landform_name(foot);
  EXPECT_NE(foot, rp::Landform::upper_slope);
}

TEST(Terrain, VValleyFloorIsACanyonAndItsInverseARidge) {
  const rp::TerrainParameters p;
  const rp::TerrainModel m = rp::analyse_terrain(grid_of(v_valley, 1000.0), p);
  // Cell column 200 has its centre at kE0 + 2.5: |x| = 2.5 there, 0.5 m above the floor line.
  const double e = kE0 + 2.5;
  EXPECT_NEAR(m.tpi_small.sample(e, kN0 + 2.5), 0.5 - 0.2 * abs_x_annulus_mean(10, 50), 0.15);
  EXPECT_NEAR(m.tpi_large.sample(e, kN0 + 2.5), 0.5 - 0.2 * abs_x_annulus_mean(100, 300), 0.3);
  EXPECT_EQ(landform_at(m, p, e, kN0), rp::Landform::canyon);
  // 600 m up the flank the ground is a plane of slope atan(0.2) = 11.3 degrees.
  EXPECT_EQ(landform_at(m, p, kE0 + 600.0, kN0), rp::Landform::open_slope);
  const rp::TerrainModel ridge = rp::analyse_terrain(
      grid_of([](double e2, double n2) { return 600.0 - v_valley(e2, n2); }, 1000.0), p);
  EXPECT_EQ(landform_at(ridge, p, e, kN0), rp::Landform::mountain_top);
}

TEST(Terrain, TpiNeedsEnoughOfItsAnnulus) {
  rp::Grid grid = grid_of([](double, double) { return 100.0; }, 200.0);
  // Only a 20 m wide strip has elevation: the 10..50 m annulus is mostly empty there.
  for (std::size_t row = 0; row < grid.spec.rows; ++row) {
    for (std::size_t col = 0; col < grid.spec.cols; ++col) {
      if (std::abs(grid.spec.centre_easting(col) - kE0) > 10.0) grid.at(col, row) = NAN;
    }
  }
  const rp::Grid tpi = rp::topographic_position(grid, 10.0, 50.0, 0.5);
  EXPECT_TRUE(std::isnan(tpi.sample(kE0 + 2.5, kN0 + 2.5)));
  const rp::Grid lenient = rp::topographic_position(grid, 10.0, 50.0, 0.1);
  EXPECT_NEAR(lenient.sample(kE0 + 2.5, kN0 + 2.5), 0.0, 1e-6);
}

TEST(Terrain, TpiOfOneRaisedCellIsItsShareOfTheAnnulus) {
  // Flat at 0 m but one cell of 100 m, 4 cells (20 m) east of the cell asked about. The small
  // annulus 10 < d <= 50 m on 5 m cells holds the cells at 2 < d <= 10 cells: 317 lattice points
  // within radius 10 (Gauss's circle problem) minus 13 within radius 2 = 304 cells, so the TPI
  // is 0 - 100 / 304. A raised cell at exactly 2 cells is inside the inner disc: TPI 0.
  rp::Grid grid = grid_of([](double, double) { return 0.0; }, 200.0);  // 80 x 80 cells
  grid.at(44, 40) = 100.0f;
  rp::AnnulusTpi tpi(grid, 10.0, 50.0, 0.5);
  EXPECT_FLOAT_EQ(tpi.at(40, 40), static_cast<float>(-100.0 / 304.0));
  EXPECT_FLOAT_EQ(tpi.at(42, 40), 0.0f);  // 2 cells away: not in the annulus
  // 10 cells away: on the outer disc's edge, in; 11: outside.
  EXPECT_FLOAT_EQ(tpi.at(34, 40), static_cast<float>(-100.0 / 304.0));
  EXPECT_FLOAT_EQ(tpi.at(33, 40), 0.0f);
}

TEST(Terrain, TpiPrefixSumBandGivesTheSameInAnyOrder) {
  // A tall grid (60 x 600 cells) rising 1 m a row northwards, with two cells raised 100 m
  // above it, 540 rows apart. The prefix sums are held for a band of 184 rows (8 query windows
  // of 21 + 2 rows), so a sweep north moves the band forward, asking at the far raised cell
  // jumps it, and coming back south restarts it. By hand: the annulus is symmetric about its
  // cell, so the plane's mean over it is the cell's own height (all sums are whole numbers:
  // exact) and the TPI is 0; 4 cells from a raised cell it is -100 / 304 (as above), and at
  // the raised cell +100. A row of the band read at the wrong place would be off by metres.
  rp::Grid grid(rp::grid_covering(kZone, kE0, kN0, kE0 + 300.0, kN0 + 3000.0, 0.0, 5.0));
  ASSERT_EQ(grid.spec.rows, 600u);
  for (std::size_t row = 0; row < grid.spec.rows; ++row) {
    for (std::size_t col = 0; col < grid.spec.cols; ++col) grid.at(col, row) = float(row);
  }
  grid.at(30, 40) += 100.0f;
  grid.at(30, 580) += 100.0f;
  const double share = -100.0 / 304.0;
  rp::AnnulusTpi tpi(grid, 10.0, 50.0, 0.5);
  EXPECT_NEAR(tpi.at(26, 40), share, 1e-4);
  for (std::size_t row = 41; row < 400; ++row) EXPECT_EQ(tpi.at(20, row), 0.0f) << row;
  EXPECT_NEAR(tpi.at(30, 576), share, 1e-4);  // a jump past the band
  EXPECT_EQ(tpi.at(30, 150), 0.0f);           // back south: the band restarts
  EXPECT_NEAR(tpi.at(30, 36), share, 1e-4);
  EXPECT_NEAR(tpi.at(34, 40), share, 1e-4);
  EXPECT_NEAR(tpi.at(30, 570), share, 1e-4);  // 10 rows from the raised cell: on the edge, in
  EXPECT_EQ(tpi.at(30, 569), 0.0f);           // 11 rows: out
  EXPECT_NEAR(tpi.at(30, 580), 100.0, 1e-4);
}

TEST(Terrain, LargeTpiAtABlockCentreIsItsOwnBlocksMean) {
  // The large annulus (100..300 m on 5 m cells) runs on 15 m blocks; a cell at a block's centre
  // takes that block's mean without interpolating. On a plane rising 0.1 m per metre east, the
  // annulus mean around a block centre is the plane there, so the TPI of the centre cell is 0;
  // the block one to the east or west would give -1.5 or +1.5 m.
  rp::Grid grid = grid_of([](double e, double) { return 0.1 * (e - kE0); }, 1000.0);
  ASSERT_EQ(grid.spec.cols, 400u);
  rp::AnnulusTpi tpi(grid, 100.0, 300.0, 0.5);
  for (const std::size_t block : {21u, 40u, 66u, 90u, 100u}) {
    const std::size_t centre = 3 * block + 1;  // cells 3b..3b+2 form block b
    EXPECT_NEAR(tpi.at(centre, 200), 0.0, 1e-3) << centre;
    EXPECT_NEAR(tpi.at(200, centre), 0.0, 1e-3) << centre;
    EXPECT_NEAR(tpi.at(centre + 1, 200), 0.0, 1e-3) << centre;  // between centres: bilinear
  }
}

TEST(Terrain, TpiAtSingleCellsIsTheWholeGridsTpi) {
  // The build computes TPI only at the cells it samples (block means on demand); those cells
  // must hold exactly what the whole-grid computation gives, for the small annulus (cells) and
  // the large one (15 m blocks, interpolated), also next to a void.
  rp::Grid grid = grid_of(gaussian_hill, 1000.0);
  for (std::size_t row = 150; row < 170; ++row) {
    for (std::size_t col = 40; col < 90; ++col) grid.at(col, row) = NAN;
  }
  for (const auto& [inner_m, outer_m] : {std::pair{10.0, 50.0}, std::pair{100.0, 300.0}}) {
    const rp::Grid whole = rp::topographic_position(grid, inner_m, outer_m, 0.5);
    // South to north (the build's order: the prefix sums' band moves north) and north to south
    // (every query restarts the band): the same bits.
    rp::AnnulusTpi lazy(grid, inner_m, outer_m, 0.5), backwards(grid, inner_m, outer_m, 0.5);
    std::size_t compared = 0, valid = 0;
    for (std::size_t row = 3; row < grid.spec.rows; row += 7) {
      for (std::size_t col = 1; col < grid.spec.cols; col += 11) {
        const float expected = whole.at(col, row), got = lazy.at(col, row);
        const std::size_t back_row = grid.spec.rows - 1 - row;
        const float back_expected = whole.at(col, back_row), back = backwards.at(col, back_row);
        if (std::isnan(expected)) {
          EXPECT_TRUE(std::isnan(got)) << col << " " << row;
        } else {
          EXPECT_EQ(got, expected) << col << " " << row;
          ++valid;
        }
        if (std::isnan(back_expected)) {
          EXPECT_TRUE(std::isnan(back)) << col << " " << back_row;
        } else {
          EXPECT_EQ(back, back_expected) << col << " " << back_row;
        }
        ++compared;
      }
    }
    EXPECT_GT(valid, compared / 2);
    EXPECT_LT(valid, compared);  // the void and the edges have none
  }
}

TEST(Terrain, TinInterpolationIsExactOnAPlaneAndDoesNotExtrapolate) {
  // Pseudo-random points (a fixed LCG) inside a 400 m square, on the plane z = 50 + 0.03 e - 0.02
  // n.
  const auto plane = [](double e, double n) { return 50.0 + 0.03 * (e - kE0) - 0.02 * (n - kN0); };
  std::vector<rp::ElevationPoint> points;
  std::uint64_t state = 12345;
  const auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / double(1ULL << 53);
  };
  for (int i = 0; i < 2000; ++i) {
    const double e = kE0 - 200 + 400 * next(), n = kN0 - 200 + 400 * next();
    points.push_back({e, n, plane(e, n)});
  }
  rp::Grid grid(rp::grid_covering(kZone, kE0 - 300, kN0 - 300, kE0 + 300, kN0 + 300, 0, 5));
  const std::size_t filled = rp::fill_from_points(grid, points, 100.0);
  EXPECT_GT(filled, 5000u);  // about 80 x 80 cells lie inside the hull
  for (double d : {-150.0, -37.5, 0.0, 62.5, 150.0}) {
    EXPECT_NEAR(grid.sample(kE0 + d, kN0 - d), plane(kE0 + d, kN0 - d), 2e-3);
  }
  EXPECT_TRUE(std::isnan(grid.sample(kE0 + 250, kN0)));  // outside the hull
  // With a 1 m edge limit every triangle spans a "gap".
  rp::Grid strict(grid.spec);
  EXPECT_EQ(rp::fill_from_points(strict, points, 1.0), 0u);
}

namespace {

/// Writes a GeoTIFF in UTM 33N (EPSG:32633) with `cell_m` pixels over kE0 +- half_m, north up,
/// values from `z`; `nodata` cells where `is_void` says so.
std::string write_geotiff(const std::string& path, const Surface& z, double half_m, double cell_m,
                          const std::function<bool(double, double)>& is_void = nullptr) {
  GDALAllRegister();
  const int size = static_cast<int>(2 * half_m / cell_m);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDataset* ds = driver->Create(path.c_str(), size, size, 1, GDT_Float32, nullptr);
  double gt[6] = {kE0 - half_m, cell_m, 0, kN0 + half_m, 0, -cell_m};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(32633);
  ds->SetSpatialRef(&srs);
  std::vector<float> pixels(static_cast<std::size_t>(size) * size);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      const double e = gt[0] + (c + 0.5) * cell_m, n = gt[3] - (r + 0.5) * cell_m;
      pixels[static_cast<std::size_t>(r) * size + c] =
          is_void && is_void(e, n) ? -9999.0f : static_cast<float>(z(e, n));
    }
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (is_void) band->SetNoDataValue(-9999.0);
  EXPECT_EQ(
      band->RasterIO(GF_Write, 0, 0, size, size, pixels.data(), size, size, GDT_Float32, 0, 0),
      CE_None);
  GDALClose(ds);
  return path;
}

}  // namespace

TEST(Terrain, RasterIsSampledBilinearlyWithItsNodata) {
  TempDir dir;
  const auto plane = [](double e, double n) { return 80.0 + 0.04 * (e - kE0) + 0.01 * (n - kN0); };
  const std::string tif = write_geotiff(dir.file("plane.tif"), plane, 500.0, 10.0);
  rp::Grid grid(rp::grid_covering(kZone, kE0 - 300, kN0 - 300, kE0 + 300, kN0 + 300, 0, 5));
  EXPECT_EQ(rp::fill_from_raster(grid, tif), grid.spec.size());
  for (double d : {-250.0, -12.5, 0.0, 37.5, 250.0}) {
    EXPECT_NEAR(grid.sample(kE0 + d, kN0 + d / 2), plane(kE0 + d, kN0 + d / 2), 1e-3);
  }
  // A void of 60 m x 60 m: cells whose bilinear neighbourhood touches it stay NaN...
  const auto in_void = [](double e, double n) {
    return std::abs(e - kE0) < 30.0 && std::abs(n - kN0) < 30.0;
  };
  const std::string holed = write_geotiff(dir.file("holed.tif"), plane, 500.0, 10.0, in_void);
  rp::Grid with_void(grid.spec);
  const std::size_t filled = rp::fill_from_raster(with_void, holed);
  EXPECT_LT(filled, grid.spec.size());
  EXPECT_TRUE(std::isnan(with_void.sample(kE0, kN0)));
  EXPECT_NEAR(with_void.sample(kE0 + 100, kN0), plane(kE0 + 100, kN0), 1e-3);
  // ... until fill_voids closes them from the valid neighbours (35 m away at most).
  rp::Grid too_short = with_void;
  rp::fill_voids(too_short, 10.0);
  EXPECT_TRUE(std::isnan(too_short.sample(kE0, kN0)));
  EXPECT_GT(rp::fill_voids(with_void, 100.0), 0u);
  EXPECT_NEAR(with_void.sample(kE0, kN0), plane(kE0, kN0), 1.0);
  EXPECT_EQ(with_void.count_valid(), grid.spec.size());
}

TEST(Terrain, RasterOpenedOnceFillsManyGrids) {
  // The build opens a raster once per thread and fills every tile from it: a second grid, half
  // off the raster, gets the plane's values where the raster's pixel centres surround it.
  TempDir dir;
  const auto plane = [](double e, double n) { return 80.0 + 0.04 * (e - kE0) + 0.01 * (n - kN0); };
  const std::string tif = write_geotiff(dir.file("plane.tif"), plane, 500.0, 10.0);
  const rp::RasterElevation raster(tif, kZone);
  rp::Grid inside(rp::grid_covering(kZone, kE0 - 300, kN0 - 300, kE0 + 300, kN0 + 300, 0, 5));
  EXPECT_EQ(raster.fill(inside), inside.spec.size());
  EXPECT_NEAR(inside.sample(kE0 + 37.5, kN0 - 12.5), plane(kE0 + 37.5, kN0 - 12.5), 1e-3);
  // 80 x 40 cells from E0 + 300 m: centres E0 + 302.5 + 5 k; the last pixel centre is at
  // E0 + 495 m, so columns k = 0..38 have values: 39 x 40 cells.
  rp::Grid half_off(rp::grid_covering(kZone, kE0 + 300, kN0 - 100, kE0 + 700, kN0 + 100, 0, 5));
  ASSERT_EQ(half_off.spec.cols, 80u);
  ASSERT_EQ(half_off.spec.rows, 40u);
  EXPECT_EQ(raster.fill(half_off), 39u * 40u);
  EXPECT_NEAR(half_off.at(38, 0), plane(kE0 + 492.5, kN0 - 97.5), 1e-3);
  EXPECT_TRUE(std::isnan(half_off.at(39, 0)));
  // Filled cells are kept: a second fill adds none.
  EXPECT_EQ(raster.fill(half_off), 0u);
  EXPECT_THROW(rp::RasterElevation(dir.file("missing.tif"), kZone), rp::InputError);
}

TEST(Terrain, GridOnTheRastersLastPixelColumnIsNotFilled) {
  // 8 m pixels over kE0 +- 512 m (128 columns, the last centred at kE0 + 508 m, raster column
  // 127) in the grid's own CRS: every raster coordinate below is exact. A cell needs a pixel to
  // its right, except on the last column, where it takes that pixel's value (weights 0 and 1)
  // when the grid also has cells west of it...
  TempDir dir;
  const auto plane = [](double e, double n) { return 80.0 + 0.04 * (e - kE0) + 0.01 * (n - kN0); };
  const rp::RasterElevation raster(write_geotiff(dir.file("plane8.tif"), plane, 512.0, 8.0), kZone);
  const double last_centre_e = kE0 + 508.0;
  rp::Grid west_of_it(rp::grid_covering(kZone, last_centre_e - 6, kN0 - 50, last_centre_e + 2,
                                        kN0 + 50, 0.0, 4.0, 2.0));
  ASSERT_EQ(west_of_it.spec.cols, 2u);  // centres at last_centre_e - 4 and last_centre_e
  ASSERT_EQ(west_of_it.spec.rows, 25u);
  EXPECT_EQ(raster.fill(west_of_it), 2u * 25u);
  EXPECT_NEAR(west_of_it.at(1, 0), plane(last_centre_e, west_of_it.spec.centre_northing(0)), 1e-3);
  // ... but not when every cell is on or beyond it: the raster window of such a grid is one
  // pixel wide (the original two-pass fill's rule, kept bit for bit).
  rp::Grid on_it(rp::grid_covering(kZone, last_centre_e - 2, kN0 - 50, last_centre_e + 6, kN0 + 50,
                                   0.0, 4.0, 2.0));
  ASSERT_EQ(on_it.spec.cols, 2u);  // centres at last_centre_e and last_centre_e + 4
  EXPECT_EQ(raster.fill(on_it), 0u);
  EXPECT_EQ(on_it.count_valid(), 0u);
}

TEST(Terrain, GeographicRasterIsTransformed) {
  // A raster in EPSG:4326 whose value is a linear function of lon/lat: the grid cell at a UTM
  // point must get the function's value at that point's lon/lat.
  TempDir dir;
  const std::string path = dir.file("geo.tif");
  GDALAllRegister();
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
      path.c_str(), 200, 200, 1, GDT_Float64, nullptr);
  double gt[6] = {14.99, 0.0001, 0, 50.02, 0, -0.0001};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(4326);
  ds->SetSpatialRef(&srs);
  const auto f = [](double lon, double lat) {
    return 1000.0 * (lon - 15.0) + 500.0 * (lat - 50.0);
  };
  std::vector<double> pixels(200 * 200);
  for (int r = 0; r < 200; ++r) {
    for (int c = 0; c < 200; ++c)
      pixels[r * 200 + c] = f(gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5]);
  }
  ASSERT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 200, 200, pixels.data(), 200, 200,
                                           GDT_Float64, 0, 0),
            CE_None);
  GDALClose(ds);
  const geo::UtmPoint centre = geo::wgs84_to_utm(50.01, 15.0, kZone);
  rp::Grid grid(rp::grid_covering(kZone, centre.easting_m - 400, centre.northing_m - 400,
                                  centre.easting_m + 400, centre.northing_m + 400, 0, 5));
  EXPECT_EQ(rp::fill_from_raster(grid, path), grid.spec.size());
  for (double d : {-300.0, 0.0, 300.0}) {
    const double e = grid.spec.centre_easting(80) + d, n = grid.spec.centre_northing(90) - d;
    const geo::LatLon ll = geo::utm_to_wgs84(e, n, kZone);
    EXPECT_NEAR(grid.sample(e, n), f(ll.lon_deg, ll.lat_deg), 1e-3);
  }
}

namespace {

/// A straight residential road along easting from kE0 - 600 to kE0 + 600 at northing kN0,
/// nodes every 20 m; the middle stretch kE0 +- `bridge_half_m` is a bridge way if > 0.
std::string road_across(double bridge_half_m = 0.0) {
  std::string body, refs_before, refs_bridge, refs_after;
  for (int i = 0; i <= 60; ++i) {
    const double e = kE0 - 600.0 + 20.0 * i;
    const geo::LatLon ll = geo::utm_to_wgs84(e, kN0, kZone);
    body += roadcross::testing::osm_node(i + 1, ll.lat_deg, ll.lon_deg);
    const std::string id = std::to_string(i + 1) + " ";
    const double x = e - kE0;
    if (bridge_half_m <= 0.0) {
      refs_before += id;
    } else if (x <= -bridge_half_m) {
      refs_before += id;
    } else if (x < bridge_half_m) {
      refs_bridge += id;
    } else {
      refs_after += id;
    }
    if (bridge_half_m > 0.0 && std::abs(std::abs(x) - bridge_half_m) < 1e-6) {
      refs_bridge += id;  // the structure's ends are shared with the road on either side
    }
  }
  body += roadcross::testing::osm_way(1, refs_before, "highway=residential;name=Hill Road");
  if (bridge_half_m > 0.0) {
    body += roadcross::testing::osm_way(2, refs_bridge, "highway=residential;bridge=yes");
    body += roadcross::testing::osm_way(3, refs_after, "highway=residential");
  }
  return roadcross::testing::osm_document(body);
}

struct SegmentRow {
  double mid_e;
  std::optional<double> elevation_m, grade_percent;
  std::optional<std::string> landform;
  std::optional<int> elevation_cost;
  std::string reasons;
};

std::vector<SegmentRow> read_segments(const std::string& db_path) {
  roadcross::sqlite::Database db(db_path, SQLITE_OPEN_READONLY);
  auto q = db.prepare(
      "SELECT (MinX + MaxX) / 2, elevation_m, grade_percent, landform, elevation_cost, reasons "
      "FROM segments JOIN rtree_segments_geom ON id = fid ORDER BY 1");
  std::vector<SegmentRow> rows;
  while (q.step()) {
    SegmentRow r;
    r.mid_e = q.column_double(0);
    if (!q.column_is_null(1)) r.elevation_m = q.column_double(1);
    if (!q.column_is_null(2)) r.grade_percent = q.column_double(2);
    if (!q.column_is_null(3)) r.landform = q.column_text(3);
    if (!q.column_is_null(4)) r.elevation_cost = static_cast<int>(q.column_int64(4));
    r.reasons = q.column_is_null(5) ? "" : q.column_text(5);
    rows.push_back(r);
  }
  return rows;
}

rp::BuildSummary build(const TempDir& dir, const std::string& osm,
                       const std::vector<std::string>& elevation, const std::string& crs,
                       const std::string& out) {
  rp::BuildOptions options;
  options.osm_path = dir.write("road.osm", osm);
  options.output_path = dir.file(out);
  // The road is 1200 m in UTM up to the centimetre the OSM coordinates are rounded to: just
  // over 10 m segments keep the count at 120.
  options.parameters.segments.max_segment_length_m = 10.01;
  // The expected values of the tests below were derived for 5 m cells (the automatic choice
  // would take the 10 m pixels of their rasters).
  options.parameters.terrain.cell_size_m = 5.0;
  for (const std::string& e : elevation) {
    options.elevation.sources.push_back({e, rp::elevation_kind_of(e)});
  }
  options.elevation.xyz_crs = crs;
  return rp::run_build(options);
}

std::string write_xyz(const std::string& path, const Surface& z, double half_m, double step_m,
                      char separator) {
  std::ofstream out(path);
  out << "easting" << separator << "northing" << separator << "altitude\r\n";
  out.precision(10);
  for (double n = kN0 - half_m; n <= kN0 + half_m; n += step_m) {
    for (double e = kE0 - half_m; e <= kE0 + half_m; e += step_m) {
      out << e << separator << n << separator << z(e, n) << "\r\n";
    }
  }
  return path;
}

}  // namespace

TEST(TerrainBuild, RoadOverAHillFromRasterAndFromXyzAgree) {
  TempDir dir;
  const std::string tif = write_geotiff(dir.file("hill.tif"), gaussian_hill, 1500.0, 10.0);
  const std::string xyz = write_xyz(dir.file("hill.csv"), gaussian_hill, 1500.0, 10.0, ';');
  build(dir, road_across(), {tif}, "", "raster.gpkg");
  const rp::BuildSummary s = build(dir, road_across(), {xyz}, "EPSG:32633", "xyz.gpkg");
  EXPECT_EQ(s.terrain.xyz_points, 301u * 301u);
  const auto raster_rows = read_segments(dir.file("raster.gpkg"));
  const auto xyz_rows = read_segments(dir.file("xyz.gpkg"));
  ASSERT_EQ(raster_rows.size(), xyz_rows.size());
  ASSERT_EQ(raster_rows.size(), 120u);  // 1200 m in segments of at most 10 m
  for (std::size_t i = 0; i < raster_rows.size(); ++i) {
    const SegmentRow& r = raster_rows[i];
    ASSERT_TRUE(r.elevation_m && xyz_rows[i].elevation_m);
    // Both are linear interpolations of the same 10 m samples (bilinear vs TIN), resampled to
    // the 5 m grid: each linear step errs by at most h^2/8 |f''| per axis, at the top
    // (f'' = 50/100^2 per m) (10^2/8 + 5^2/8) * 0.005 * 2 axes = 0.156 m.
    EXPECT_NEAR(*r.elevation_m, *xyz_rows[i].elevation_m, 0.16);
    EXPECT_NEAR(*r.elevation_m, gaussian_hill(r.mid_e, kN0), 0.16);
    EXPECT_EQ(r.landform, xyz_rows[i].landform);
  }
  // The segment at the top: mountain top, CREST_OR_DIP, the highest elevation cost on the road
  // and at least 6 of 9 over its whole window (a midslope ridge, landform cost 10, alone gives 9).
  const SegmentRow& top = raster_rows[60];
  EXPECT_NEAR(top.mid_e, kE0 + 5.0, 0.05);
  EXPECT_EQ(top.landform, "mountain_top");
  EXPECT_THAT(top.reasons, ::testing::HasSubstr("CREST_OR_DIP"));
  EXPECT_GE(top.elevation_cost, 6);
  for (const SegmentRow& r : raster_rows) EXPECT_LE(r.elevation_cost, top.elevation_cost);
  // The grade of a segment on the eastern flank at 150 m: dz/de of the hill (going east, down).
  const SegmentRow& flank = raster_rows[75];
  const double x = flank.mid_e - kE0;
  EXPECT_NEAR(*flank.grade_percent,
              -100.0 * x / (100.0 * 100.0) * (gaussian_hill(flank.mid_e, kN0) - 300.0), 0.5);
  // The foot: no crest.
  const SegmentRow& foot = raster_rows[0];
  EXPECT_THAT(foot.reasons, ::testing::Not(::testing::HasSubstr("CREST_OR_DIP")));
  EXPECT_THAT(foot.reasons, ::testing::Not(::testing::HasSubstr("NO_ELEVATION")));
}

TEST(TerrainBuild, PartialCoverageGivesNoElevationAndRenormalisedRank) {
  TempDir dir;
  // The raster covers only the western half of the road (e < kE0 - 100).
  const auto west_only = [](double e, double) { return e < kE0 - 100.0; };
  const std::string tif = write_geotiff(
      dir.file("half.tif"), [](double, double) { return 250.0; }, 1500.0, 10.0,
      [&](double e, double n) { return !west_only(e, n); });
  rp::TerrainParameters p;
  const rp::BuildSummary s = build(dir, road_across(), {tif}, "", "half.gpkg");
  const auto rows = read_segments(dir.file("half.gpkg"));
  std::size_t without = 0;
  for (const SegmentRow& r : rows) {
    if (r.mid_e < kE0 - 100.0 - p.void_fill_max_m - 20.0) {
      EXPECT_TRUE(r.elevation_cost.has_value());
      EXPECT_NEAR(*r.elevation_m, 250.0, 1e-3);
    }
    if (r.mid_e > kE0 - 100.0 + p.void_fill_max_m + 20.0) {
      EXPECT_FALSE(r.elevation_m.has_value());
      EXPECT_THAT(r.reasons, ::testing::HasSubstr("NO_ELEVATION"));
    }
    without += r.elevation_cost ? 0 : 1;
  }
  EXPECT_EQ(s.terrain.segments_without_elevation, without);
  EXPECT_GT(without, 40u);
  EXPECT_THAT(s.notes, ::testing::Contains(::testing::HasSubstr(
                           std::to_string(without) + " of 120 segments have no elevation")));
}

TEST(TerrainBuild, BridgeTakesItsElevationFromItsEnds) {
  TempDir dir;
  // A V valley 60 m deep at the road's middle; a bridge spans kE0 +- 200 m, whose ends lie at
  // 300 + 0.2 * 200 = 340 m: the deck is level at 340 m, not down in the valley.
  const std::string tif = write_geotiff(dir.file("valley.tif"), v_valley, 1500.0, 10.0);
  const rp::BuildSummary s = build(dir, road_across(200.0), {tif}, "", "bridge.gpkg");
  EXPECT_EQ(s.terrain.structure_segments, 40u);
  for (const SegmentRow& r : read_segments(dir.file("bridge.gpkg"))) {
    if (std::abs(r.mid_e - kE0) < 200.0) {
      EXPECT_EQ(r.landform, "bridge");
      EXPECT_NEAR(*r.elevation_m, 340.0, 0.05);
      EXPECT_NEAR(*r.grade_percent, 0.0, 0.05);
    } else {
      EXPECT_NEAR(*r.elevation_m, v_valley(r.mid_e, kN0), 0.05);
    }
  }
}

TEST(TerrainBuild, ElevationThatMissesTheRoadsIsAnError) {
  TempDir dir;
  // A raster 50 km away.
  const std::string far = dir.file("far.tif");
  {
    GDALAllRegister();
    GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
        far.c_str(), 10, 10, 1, GDT_Float32, nullptr);
    double gt[6] = {kE0 + 50000, 10, 0, kN0 + 50000, 0, -10};
    ds->SetGeoTransform(gt);
    OGRSpatialReference srs;
    srs.importFromEPSG(32633);
    ds->SetSpatialRef(&srs);
    std::vector<float> zeros(100, 1.0f);
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 10, 10, zeros.data(), 10, 10,
                                             GDT_Float32, 0, 0),
              CE_None);
    GDALClose(ds);
  }
  try {
    build(dir, road_across(), {far}, "", "far.gpkg");
    FAIL() << "a DEM beside the map was accepted";
  } catch (const rp::InputError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("far.tif"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("does not overlap the roads"));
  }
  EXPECT_FALSE(std::ifstream(dir.file("far.gpkg")).good());  // no half-written output
  // Not a raster at all.
  const std::string junk = dir.write("junk.tif", "this is not a raster\n");
  EXPECT_THROW(build(dir, road_across(), {junk}, "", "junk.gpkg"), rp::InputError);
}

TEST(Terrain, TinOnRealDmr5gPointsCoversTheirSheet) {
  // maps/zabaged/BILO48_5g_40k.csv: 40 329 real DMR 5G points in S-JTSK covering E
  // -486 015.78...-485 000.00, N -1 116 591.75...-1 116 000.00 (PROVENANCE.md), heights
  // 240.29...255.32 m. Linear interpolation in triangles never leaves the range of the
  // vertices, and the filled cells must cover that rectangle's area (1 015.78 m x 591.75 m =
  // 601 088 m^2; Krovak's and UTM's scale factors differ by < 0.1 %), less the boundary cells.
  const geo::UtmZone zone{34, true};
  std::vector<rp::ElevationPoint> points =
      rp::read_xyz(ROADCROSS_MAPS_DIR "/zabaged/BILO48_5g_40k.csv");
  std::vector<double> x, y;
  for (const auto& p : points) x.push_back(p.x), y.push_back(p.y);
  rp::CrsTransform(rp::detect_xyz_crs("bilo", points), zone).to_utm(x, y);
  double min_e = 1e18, min_n = 1e18, max_e = -1e18, max_n = -1e18;
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i].x = x[i], points[i].y = y[i];
    min_e = std::min(min_e, x[i]), max_e = std::max(max_e, x[i]);
    min_n = std::min(min_n, y[i]), max_n = std::max(max_n, y[i]);
  }
  rp::Grid grid(rp::grid_covering(zone, min_e, min_n, max_e, max_n, 20.0, 5.0));
  const std::size_t filled = rp::fill_from_points(grid, points, 100.0);
  const double area_m2 = double(filled) * 25.0;
  EXPECT_GT(area_m2, 0.97 * 601088.0);
  EXPECT_LT(area_m2, 1.00 * 601088.0);
  for (const float z : grid.values) {
    if (std::isnan(z)) continue;
    EXPECT_GE(z, 240.29f - 1e-3f);
    EXPECT_LE(z, 255.33f);
  }
}

TEST(TerrainBuild, RoadUpAPlaneHasItsGradeSlopeAndCost) {
  // z = 200 + 0.1 (e - kE0): the east-running road climbs 10 %, the terrain slope is
  // atan(0.1) = 5.711 degrees everywhere, TPI is 0: open slope (> 5 degrees), landform cost 3,
  // elevation cost min(9, floor(3)) = 3, no crest.
  TempDir dir;
  const auto plane = [](double e, double) { return 200.0 + 0.1 * (e - kE0); };
  const std::string tif = write_geotiff(dir.file("plane.tif"), plane, 1500.0, 10.0);
  build(dir, road_across(), {tif}, "", "plane.gpkg");
  roadcross::sqlite::Database db(dir.file("plane.gpkg"), SQLITE_OPEN_READONLY);
  auto q = db.prepare(
      "SELECT grade_percent, slope_deg, tpi_small_m, tpi_large_m, landform, "
      "elevation_cost, reasons FROM segments");
  int rows = 0;
  while (q.step()) {
    ++rows;
    EXPECT_NEAR(q.column_double(0), 10.0, 0.01);
    EXPECT_NEAR(q.column_double(1), std::atan(0.1) * 180.0 / kPi, 1e-3);
    EXPECT_NEAR(q.column_double(2), 0.0, 1e-3);
    EXPECT_NEAR(q.column_double(3), 0.0, 1e-3);
    EXPECT_EQ(q.column_text(4), "open_slope");
    EXPECT_EQ(q.column_int64(5), 3);
    EXPECT_THAT(q.column_text(6), ::testing::Not(::testing::HasSubstr("CREST_OR_DIP")));
  }
  EXPECT_EQ(rows, 120);
}

TEST(TerrainBuild, TilesGiveTheSameTermsAsOneGrid) {
  // The road over the hill analysed as one 10 km tile and as 150 m tiles (8 tiles along the
  // road, each with its own 305 m halo): every segment's terms must agree, since a cell's
  // annuli, blocks and voids do not depend on the tile that computes it.
  TempDir dir;
  const std::string tif = write_geotiff(dir.file("hill.tif"), gaussian_hill, 1500.0, 10.0);
  const rp::BuildSummary one = build(dir, road_across(), {tif}, "", "one.gpkg");
  rp::BuildOptions options;
  options.osm_path = dir.write("road.osm", road_across());
  options.output_path = dir.file("tiled.gpkg");
  options.parameters.segments.max_segment_length_m = 10.01;
  options.parameters.terrain.tile_size_m = 150.0;
  options.parameters.terrain.cell_size_m = 5.0;  // as build() above
  options.elevation.sources.push_back({tif, rp::ElevationKind::raster});
  const rp::BuildSummary tiled = rp::run_build(options);
  EXPECT_EQ(one.terrain.tiles, 1u);
  EXPECT_EQ(tiled.terrain.tiles, 8u);  // 1200 m of road / 150 m
  const auto a = read_segments(dir.file("one.gpkg"));
  const auto b = read_segments(dir.file("tiled.gpkg"));
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(*a[i].elevation_m, *b[i].elevation_m, 1e-4) << i;
    EXPECT_NEAR(*a[i].grade_percent, *b[i].grade_percent, 1e-4) << i;
    EXPECT_EQ(a[i].landform, b[i].landform) << i;
    EXPECT_EQ(a[i].elevation_cost, b[i].elevation_cost) << i;
    EXPECT_EQ(a[i].reasons, b[i].reasons) << i;
  }
}

TEST(TerrainBuild, XyzSplitWithASmallMemoryBudgetGivesTheSameTerms) {
  // The hill's 90 601 XYZ points over 150 m tiles: held in memory (the default budget), and
  // with a budget of ~2 200 points so that they are spilled to the temporary file many times
  // and each tile reads its own back. Same points per tile, same order: the same TINs, terms
  // and stored grid. Nothing but the outputs is left in the directory.
  TempDir dir;
  const std::string xyz = write_xyz(dir.file("hill.xyz"), gaussian_hill, 1500.0, 10.0, ' ');
  const auto run = [&](const std::string& out, double budget_mib) {
    rp::BuildOptions options;
    options.osm_path = dir.write("road.osm", road_across());
    options.output_path = dir.file(out);
    options.parameters.segments.max_segment_length_m = 10.01;
    options.parameters.terrain.tile_size_m = 150.0;
    options.parameters.terrain.xyz_memory_mib = budget_mib;
    options.elevation.sources.push_back({xyz, rp::ElevationKind::xyz});
    options.elevation.xyz_crs = "EPSG:32633";
    options.elevation.spill_dir = dir.path();
    return rp::run_build(options);
  };
  const rp::BuildSummary held = run("held.gpkg", 1024.0);
  const rp::BuildSummary split = run("split.gpkg", 0.05);
  EXPECT_EQ(held.terrain.xyz_spilled_points, 0u);
  EXPECT_GT(split.terrain.xyz_spilled_points, 90601u / 2);
  EXPECT_EQ(split.terrain.xyz_points, 90601u);
  EXPECT_EQ(split.terrain.tiles, 8u);
  EXPECT_EQ(split.terrain.cells_with_elevation, held.terrain.cells_with_elevation);
  const auto a = read_segments(dir.file("held.gpkg"));
  const auto b = read_segments(dir.file("split.gpkg"));
  ASSERT_EQ(a.size(), 120u);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(a[i].elevation_m && b[i].elevation_m);
    EXPECT_EQ(*a[i].elevation_m, *b[i].elevation_m) << i;
    EXPECT_EQ(*a[i].grade_percent, *b[i].grade_percent) << i;
    EXPECT_EQ(a[i].landform, b[i].landform) << i;
    EXPECT_EQ(a[i].elevation_cost, b[i].elevation_cost) << i;
  }
  roadcross::sqlite::Database db(dir.file("held.gpkg"), SQLITE_OPEN_READONLY);
  db.exec("ATTACH '" + dir.file("split.gpkg") + "' AS split");
  auto q = db.prepare(
      "SELECT (SELECT count(*) FROM main.terrain), (SELECT count(*) FROM (SELECT zoom_level, "
      "tile_column, tile_row, tile_data FROM main.terrain EXCEPT SELECT zoom_level, "
      "tile_column, tile_row, tile_data FROM split.terrain))");
  ASSERT_TRUE(q.step());
  EXPECT_GT(q.column_int64(0), 0);
  EXPECT_EQ(q.column_int64(1), 0);  // every stored tile byte for byte
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    left.push_back(entry.path().filename().string());
  }
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"held.gpkg", "hill.xyz", "road.osm", "split.gpkg"}));
}

// --- the automatic terrain cell size (terrain.cell_size_m = 0) ---------------------------------

// The statistics' lattices, steps worked by hand from the rule (cost-model.md "TPI statistics"):
// small step = min(round(20 m / cell), floor(sqrt(cells / 250 000))), at least 1; every cell
// when that bound is <= 1; large step = 3 x small rounded up to a multiple of the large
// annulus' block factor floor(300 m / cell / 20), offset half a block.
TEST(TerrainStatistics, LatticeStepsFollowTheGridAndTheCellSize) {
  const auto lattice = [](std::size_t cells, double cell_m) {
    rp::TerrainParameters p;
    p.cell_size_m = cell_m;
    const rp::StatisticsLattice l = rp::statistics_lattice(cells, p);
    return std::array<long long, 3>{l.small_step, l.large_step, l.large_offset};
  };
  using Steps = std::array<long long, 3>;
  // Monaco at 5 m (3.2 M cells): bound 3 < round(4): 15 m; factor 3: (9 + 2) / 3 * 3 = 9: 45 m.
  EXPECT_EQ(lattice(3'200'000, 5.0), (Steps{3, 9, 1}));
  // A country at 5 m: 20 m and (12 + 2) / 3 * 3 = 12: 60 m.
  EXPECT_EQ(lattice(100'000'000, 5.0), (Steps{4, 12, 1}));
  // Under 1 M cells (bound 1): every cell, exact.
  EXPECT_EQ(lattice(999'999, 5.0), (Steps{1, 1, 0}));
  EXPECT_EQ(lattice(1'000'000, 5.0), (Steps{2, 6, 1}));
  // 25 m cells (SRTM 3"): round(0.8) = 1 cell for the small TPI; the large annulus is 12 cells
  // (factor 1): every 3rd cell from 0, not every cell.
  EXPECT_EQ(lattice(7'300'000, 25.0), (Steps{1, 3, 0}));
  EXPECT_EQ(lattice(900'000, 25.0), (Steps{1, 1, 0}));
}

TEST(TerrainCellSize, RuleTakesTheFinestRasterPixelFlooredAndClamped) {
  // SRTM 1" at 50 N (19.88 x 30.90 m) -> 19 m; SRTM 3" (59.6 x 92.7 m) -> the small annulus's
  // ceiling floor(50 / 2) = 25 m; a 1 m lidar raster -> the 5 m floor; the finest of several
  // wins; any XYZ input, or no raster side at all, -> 5 m.
  EXPECT_EQ(rp::automatic_cell_size_m({19.88, 30.90}, false, 50.0), 19.0);
  EXPECT_EQ(rp::automatic_cell_size_m({59.6, 92.7}, false, 50.0), 25.0);
  EXPECT_EQ(rp::automatic_cell_size_m({59.6, 92.7}, false, 45.0), 22.0);  // floor(22.5)
  EXPECT_EQ(rp::automatic_cell_size_m({1.0, 1.0}, false, 50.0), 5.0);
  EXPECT_EQ(rp::automatic_cell_size_m({59.6, 92.7, 12.5, 12.5}, false, 50.0), 12.0);
  EXPECT_EQ(rp::automatic_cell_size_m({19.88, 30.90}, true, 50.0), 5.0);
  EXPECT_EQ(rp::automatic_cell_size_m({}, false, 50.0), 5.0);
  EXPECT_EQ(rp::automatic_cell_size_m({NAN, NAN}, false, 50.0), 5.0);
  // A small annulus under 10 m leaves the floor (validation then checks it like a given value).
  EXPECT_EQ(rp::automatic_cell_size_m({30.0}, false, 8.0), 5.0);
}

namespace {

/// A constant-elevation GeoTIFF in EPSG:4326 with 1 arc-second pixels over the road of
/// road_across() (lon 15 +- 0.02, lat 50.0 +- 0.01).
std::string write_arc_second_geotiff(const std::string& path) {
  GDALAllRegister();
  const int cols = 144, rows = 72;  // 0.04 and 0.02 degrees
  GDALDataset* ds = GetGDALDriverManager()->GetDriverByName("GTiff")->Create(
      path.c_str(), cols, rows, 1, GDT_Float32, nullptr);
  const double arc_second = 1.0 / 3600.0;
  const geo::LatLon road = geo::utm_to_wgs84(kE0, kN0, kZone);
  double gt[6] = {15.0 - 72 * arc_second,         arc_second, 0,
                  road.lat_deg + 36 * arc_second, 0,          -arc_second};
  ds->SetGeoTransform(gt);
  OGRSpatialReference srs;
  srs.importFromEPSG(4326);
  ds->SetSpatialRef(&srs);
  std::vector<float> pixels(static_cast<std::size_t>(cols) * rows, 250.0f);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, cols, rows, pixels.data(), cols, rows,
                                           GDT_Float32, 0, 0),
            CE_None);
  GDALClose(ds);
  return path;
}

rp::BuildSummary build_auto(const TempDir& dir, const std::vector<std::string>& elevation,
                            const std::string& out, double cell_size_m = 0.0) {
  rp::BuildOptions options;
  options.osm_path = dir.write("road.osm", road_across());
  options.output_path = dir.file(out);
  options.parameters.terrain.cell_size_m = cell_size_m;
  for (const std::string& e : elevation) {
    options.elevation.sources.push_back({e, rp::elevation_kind_of(e)});
  }
  options.elevation.xyz_crs = "EPSG:32633";
  return rp::run_build(options);
}

double metadata_cell_size(const std::string& gpkg) {
  roadcross::sqlite::Database db(gpkg, SQLITE_OPEN_READONLY);
  auto q =
      db.prepare("SELECT value FROM roadcross_metadata WHERE key = 'param.terrain.cell_size_m'");
  return q.step() ? std::stod(q.column_text(0)) : -1.0;
}

}  // namespace

TEST(TerrainCellSize, GeographicRasterPixelIsMeasuredOnTheEllipsoid) {
  // By hand, WGS84 (a = 6 378 137 m, f = 1 / 298.257223563, e^2 = f (2 - f)) at the road's
  // latitude phi (~50.0 N, on zone 33's central meridian, where UTM's scale is k0 = 0.9996 in
  // every direction): one arc-second of longitude spans pi/180/3600 * N(phi) cos(phi) * k0,
  // N = a / sqrt(1 - e^2 sin^2 phi); one of latitude pi/180/3600 * M(phi) * k0,
  // M = a (1 - e^2) / (1 - e^2 sin^2 phi)^1.5. About 19.87 m and 30.88 m.
  TempDir dir;
  const std::string tif = write_arc_second_geotiff(dir.file("arc_second.tif"));
  const double phi = geo::utm_to_wgs84(kE0, kN0, kZone).lat_deg * kPi / 180.0;
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double w = 1.0 - e2 * std::sin(phi) * std::sin(phi);
  const double arc = kPi / 180.0 / 3600.0, k0 = 0.9996;
  const double lon_side_m = arc * a / std::sqrt(w) * std::cos(phi) * k0;
  const double lat_side_m = arc * a * (1.0 - e2) / std::pow(w, 1.5) * k0;
  const rp::RasterElevation::PixelSize pixel =
      rp::RasterElevation(tif, kZone).pixel_size_at(kE0, kN0);
  EXPECT_NEAR(pixel.column_m, lon_side_m, 0.005);
  EXPECT_NEAR(pixel.row_m, lat_side_m, 0.005);
  ASSERT_GT(lon_side_m, 19.0);
  ASSERT_LT(lon_side_m, 20.0);
  // The build takes floor(19.87) = 19 m cells, says so, and records them in the DB.
  const rp::BuildSummary s = build_auto(dir, {tif}, "arc_second.gpkg");
  EXPECT_EQ(s.terrain.grid.cell_m, 19.0);
  EXPECT_THAT(s.terrain.cell_size_source, ::testing::HasSubstr("arc_second.tif"));
  EXPECT_THAT(s.notes, ::testing::Contains(::testing::HasSubstr(
                           "terrain grid cell size: 19 m (automatic: finest raster")));
  EXPECT_EQ(metadata_cell_size(dir.file("arc_second.gpkg")), 19.0);
}

TEST(TerrainCellSize, UtmRasterXyzAndAGivenValue) {
  TempDir dir;
  const auto plane = [](double e, double) { return 200.0 + 0.1 * (e - kE0); };
  // A UTM raster in the DB's own zone: its 12.5 m pixels are 12.5 m -> 12 m cells.
  const std::string tif = write_geotiff(dir.file("plane12.tif"), plane, 1500.0, 12.5);
  const rp::RasterElevation::PixelSize pixel =
      rp::RasterElevation(tif, kZone).pixel_size_at(kE0 + 123.0, kN0 - 45.0);
  EXPECT_NEAR(pixel.column_m, 12.5, 1e-6);
  EXPECT_NEAR(pixel.row_m, 12.5, 1e-6);
  const rp::BuildSummary utm = build_auto(dir, {tif}, "utm.gpkg");
  EXPECT_EQ(utm.terrain.grid.cell_m, 12.0);
  EXPECT_EQ(metadata_cell_size(dir.file("utm.gpkg")), 12.0);
  // 20 m XYZ points alone, and beside the raster: 5 m (a point file's spacing is not known
  // before it is read).
  const std::string xyz = write_xyz(dir.file("plane.xyz"), plane, 1500.0, 20.0, ' ');
  const rp::BuildSummary points = build_auto(dir, {xyz}, "xyz.gpkg");
  EXPECT_EQ(points.terrain.grid.cell_m, 5.0);
  EXPECT_EQ(points.terrain.cell_size_source, "automatic: XYZ points");
  EXPECT_EQ(build_auto(dir, {tif, xyz}, "both.gpkg").terrain.grid.cell_m, 5.0);
  // A given value is used as given, finer or coarser than the rule's.
  const rp::BuildSummary given = build_auto(dir, {tif}, "given.gpkg", 8.0);
  EXPECT_EQ(given.terrain.grid.cell_m, 8.0);
  EXPECT_THAT(given.notes,
              ::testing::Contains("terrain grid cell size: 8 m (given (terrain.cell_size_m))"));
  EXPECT_EQ(build_auto(dir, {xyz}, "given_xyz.gpkg", 20.0).terrain.grid.cell_m, 20.0);
  EXPECT_EQ(metadata_cell_size(dir.file("given_xyz.gpkg")), 20.0);
  // Validation still applies to the given value.
  rp::BuildOptions bad;
  bad.osm_path = dir.write("road.osm", road_across());
  bad.output_path = dir.file("bad.gpkg");
  bad.parameters.terrain.cell_size_m = 60.0;  // above the small annulus's 50 m
  bad.elevation.sources.push_back({tif, rp::ElevationKind::raster});
  EXPECT_THROW(rp::run_build(bad), rp::ParameterError);
  bad.parameters.terrain.cell_size_m = 0.25;  // neither automatic nor in [0.5, 100]
  EXPECT_THROW(rp::run_build(bad), rp::ParameterError);
}
