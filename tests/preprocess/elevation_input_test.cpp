// XYZ point files (separators, header, line ends, bad lines), CRS detection and the S-JTSK
// transformation checked against published coordinates.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace rp = roadcross::preprocess;
using roadcross::testing::TempDir;
using ::testing::HasSubstr;

namespace {

std::string error_of(const std::string& path) {
  try {
    rp::read_xyz(path);
  } catch (const rp::InputError& e) {
    return e.what();
  }
  return "";
}

void expect_two_points(const std::vector<rp::ElevationPoint>& p) {
  ASSERT_EQ(p.size(), 2u);
  EXPECT_DOUBLE_EQ(p[0].x, -485261.875);
  EXPECT_DOUBLE_EQ(p[0].y, -1116001.75);
  EXPECT_DOUBLE_EQ(p[0].z, 244.3);
  EXPECT_DOUBLE_EQ(p[1].x, -485000.0);
  EXPECT_DOUBLE_EQ(p[1].y, -1116000.5);
  EXPECT_DOUBLE_EQ(p[1].z, 250.0);
}

}  // namespace

TEST(Xyz, EverySeparatorIsAccepted) {
  TempDir dir;
  expect_two_points(rp::read_xyz(
      dir.write("space.xyz", "-485261.875 -1116001.75 244.3\n-485000 -1116000.5 250\n")));
  expect_two_points(rp::read_xyz(
      dir.write("tab.xyz", "-485261.875\t-1116001.75\t244.3\n-485000\t-1116000.5\t250\n")));
  expect_two_points(rp::read_xyz(
      dir.write("comma.csv", "-485261.875,-1116001.75,244.3\n-485000,-1116000.5,250\n")));
  expect_two_points(rp::read_xyz(
      dir.write("semicolon.csv", "-485261.875;-1116001.75;244.3\n-485000;-1116000.5;250\n")));
  // Runs of separators and trailing ones (the DMR 5G files end each line with a space).
  expect_two_points(rp::read_xyz(
      dir.write("runs.xyz", "-485261.875   -1116001.75 \t 244.3 \n-485000 -1116000.5 250  \n")));
}

TEST(Xyz, HeaderWindowsLineEndsAndBlankLines) {
  TempDir dir;
  expect_two_points(rp::read_xyz(dir.write(
      "crlf.xyz", "X Y Z\r\n-485261.875 -1116001.75 244.3\r\n\r\n-485000 -1116000.5 250\r\n")));
  expect_two_points(rp::read_xyz(
      dir.write("no_final_newline.xyz", "-485261.875 -1116001.75 244.3\n-485000 -1116000.5 250")));
  // Exponents are numbers, not a header.
  const auto p = rp::read_xyz(dir.write("exp.xyz", "1e3 2E3 3.5e1\n"));
  ASSERT_EQ(p.size(), 1u);
  EXPECT_DOUBLE_EQ(p[0].x, 1000.0);
  EXPECT_DOUBLE_EQ(p[0].z, 35.0);
}

TEST(Xyz, BadLinesNameTheFileAndLine) {
  TempDir dir;
  const std::string garbage =
      dir.write("garbage.xyz", "X Y Z\n-485261.875 -1116001.75 244.3\n-485000 abc 250\n");
  EXPECT_THAT(error_of(garbage), HasSubstr(garbage + ": line 3: expected three numbers"));
  EXPECT_THAT(error_of(garbage), HasSubstr("'-485000 abc 250'"));
  // A file cut in the middle of a line: two numbers on the last line.
  const std::string truncated =
      dir.write("truncated.xyz", "-485261.875 -1116001.75 244.3\n-485000 -11160");
  EXPECT_THAT(error_of(truncated), HasSubstr("truncated.xyz: line 2: expected three numbers"));
  // A second header-like line is not a header.
  EXPECT_THAT(error_of(dir.write("two_headers.xyz", "X Y Z\nE N H\n1 2 3\n")), HasSubstr("line 2"));
  EXPECT_THAT(error_of(dir.write("four.xyz", "1 2 3 4\n")), HasSubstr("line 1"));
  EXPECT_THAT(error_of(dir.write("nan.xyz", "1 2 3\n1 2 nan\n")), HasSubstr("line 2"));
  EXPECT_THAT(error_of(dir.write("high.xyz", "1 2 3\n1 2 12000\n")),
              HasSubstr("line 2: altitude 12000 m is outside [-500, 9000] m"));
  EXPECT_THAT(error_of(dir.write("empty.xyz", "")), HasSubstr("the elevation file is empty"));
  EXPECT_THAT(error_of(dir.write("header_only.xyz", "X Y Z\n")), HasSubstr("no 'easting"));
  EXPECT_THAT(error_of(dir.file("missing.xyz")), HasSubstr("missing.xyz: cannot open"));
}

TEST(Xyz, RealDmr5gSamplesParse) {
  // maps/zabaged: header "X Y Z", space-separated with a trailing space; and tab-separated.
  const auto bilo = rp::read_xyz(ROADCROSS_MAPS_DIR "/zabaged/BILO48_5g_40k.csv");
  EXPECT_EQ(bilo.size(), 40329u);  // PROVENANCE.md: 40 329 points
  EXPECT_DOUBLE_EQ(bilo.front().x, -485261.875);
  EXPECT_DOUBLE_EQ(bilo.front().y, -1116001.75);
  EXPECT_NEAR(bilo.front().z, 244.300003, 1e-9);
  double zmin = 1e9, zmax = -1e9;
  for (const auto& p : bilo) zmin = std::min(zmin, p.z), zmax = std::max(zmax, p.z);
  EXPECT_NEAR(zmin, 240.29, 0.01);  // PROVENANCE.md: Z 240.29...255.32
  EXPECT_NEAR(zmax, 255.32, 0.01);
  const auto cloud = rp::read_xyz(ROADCROSS_MAPS_DIR "/zabaged/test_pointcloud.txt");
  EXPECT_EQ(cloud.size(), 1574u);
  EXPECT_EQ(rp::detect_xyz_crs("bilo", bilo), "EPSG:5514");
  EXPECT_EQ(rp::detect_xyz_crs("cloud", cloud), "EPSG:5514");
}

TEST(Xyz, CrsDetectionAsksForTheOptionOutsideSjtsk) {
  const std::vector<rp::ElevationPoint> utm = {{458000.0, 5547000.0, 200.0}};
  try {
    rp::detect_xyz_crs("utm.xyz", utm);
    FAIL() << "UTM values were taken for S-JTSK";
  } catch (const rp::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("utm.xyz: cannot tell the coordinate system"));
    EXPECT_THAT(e.what(), HasSubstr("--elevation-crs"));
  }
  const std::vector<rp::ElevationPoint> positive = {{485261.0, 1116001.0, 244.0}};
  try {
    rp::detect_xyz_crs("positive.xyz", positive);
    FAIL() << "positive S-JTSK axes were accepted";
  } catch (const rp::InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("positive axes"));
  }
}

TEST(CrsTransform, KrovakMatchesTheEpsgGuidanceNoteExample) {
  // IOGP Guidance Note 7-2, Krovak example: S-JTSK (EPSG:4156) lat 50°12'32.442"N,
  // lon 16°50'59.179"E (Greenwich) projects to southing X = 1 050 538.63 m, westing
  // Y = 568 991.00 m, i.e. EPSG:5514 E = -568 991.00, N = -1 050 538.63. Both go to UTM 33N
  // through the same datum shift, so they must land on the same UTM point.
  const roadcross::geo::UtmZone zone{33, true};
  const rp::CrsTransform projected("EPSG:5514", zone);
  const rp::CrsTransform geographic("EPSG:4156", zone);
  std::vector<double> x1 = {-568991.00}, y1 = {-1050538.63};
  std::vector<double> x2 = {16.0 + 50.0 / 60 + 59.179 / 3600},
                      y2 = {50.0 + 12.0 / 60 + 32.442 / 3600};
  projected.to_utm(x1, y1);
  geographic.to_utm(x2, y2);
  EXPECT_NEAR(x1[0], x2[0], 0.05);
  EXPECT_NEAR(y1[0], y2[0], 0.05);
  // And back.
  projected.from_utm(x1, y1);
  EXPECT_NEAR(x1[0], -568991.00, 0.01);
  EXPECT_NEAR(y1[0], -1050538.63, 0.01);
}

TEST(CrsTransform, DmrSampleLandsNearBilovec) {
  // PROVENANCE.md: the BILO48 sheet lies at about lat 49.69, lon 18.09 (UTM zone 34N).
  const roadcross::geo::UtmZone zone{34, true};
  const rp::CrsTransform transform("EPSG:5514", zone);
  std::vector<double> x = {-485261.875}, y = {-1116001.75};
  transform.to_utm(x, y);
  const roadcross::geo::UtmPoint expected = roadcross::geo::wgs84_to_utm(49.69, 18.09, zone);
  EXPECT_NEAR(x[0], expected.easting_m, 2000.0);
  EXPECT_NEAR(y[0], expected.northing_m, 2000.0);
}

TEST(CrsTransform, UnknownCrsIsAParameterError) {
  EXPECT_THROW(rp::CrsTransform("EPSG:999999", roadcross::geo::UtmZone{33, true}),
               rp::ParameterError);
  EXPECT_THROW(rp::CrsTransform("not a crs", roadcross::geo::UtmZone{33, true}),
               rp::ParameterError);
}

TEST(Xyz, KindFromExtension) {
  EXPECT_EQ(rp::elevation_kind_of("a/b.xyz"), rp::ElevationKind::xyz);
  EXPECT_EQ(rp::elevation_kind_of("B.CSV"), rp::ElevationKind::xyz);
  EXPECT_EQ(rp::elevation_kind_of("p.txt"), rp::ElevationKind::xyz);
  EXPECT_EQ(rp::elevation_kind_of("N50E014.hgt"), rp::ElevationKind::raster);
  EXPECT_EQ(rp::elevation_kind_of("dem.tif"), rp::ElevationKind::raster);
  EXPECT_EQ(rp::elevation_kind_of("dir.v2/dem"), rp::ElevationKind::raster);
}
