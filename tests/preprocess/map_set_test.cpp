// roadcross::MapSet over hand-written maps on both sides of the border of UTM zones 33 and 34
// (18 deg E), at 49.5 deg N:
//   West: way 100 "West Road" from (49.5, 17.990) to (49.5, 17.9999), built in zone 33
//   East: way 200 "East Road" from (49.5, 18.003) to (49.5, 18.012), built in zone 34
//   North: way 300 "North Road" from (49.5003, 17.990) to (49.5003, 17.9999), zone 33, over West
// Expected distances are computed from the ends' grid coordinates by gdaltransform
// (-s_srs EPSG:4326 -t_srs EPSG:32633 / EPSG:32634), as the distance from the query point to
// the straight line between the road's ends in the grid (the roads are single straight ways):
//   West  A (716483.370866772, 5487337.88484197)  B (717200.053182665, 5487366.39741251)
//   North A (716482.046443431, 5487371.23023743)  B (717198.724367951, 5487399.74276076)
//   East  A (283009.8839563, 5487358.03547106)    B (283661.41356255, 5487332.13618621)
//   P1 (49.5001, 17.995) -> 33N (716844.889546106, 5487363.38845728): West 11.1121 m,
//      North 22.2596 m
//   P3 (49.5002, 17.995) -> 33N (716844.447332373, 5487374.50358116): West 22.2360 m,
//      North 11.1357 m
//   P2 (49.4999, 18.008) -> 34N (283371.402976411, 5487332.52222129): East 11.1335 m
//   Q (49.5, 18.0002), in zone 34 but near the border -> 33N (717221.770812755,
//      5487367.26290318): West's end B 21.7349 m; -> 34N (282807.186027574, 5487366.10893488):
//      East's end A 202.8586 m
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>

#include "osm_fixture.hpp"
#include "roadcross/map_set.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
using roadcross::Map;
using roadcross::MapSet;
using roadcross::Position;
using roadcross::StatusCode;
using roadcross::geo::UtmZone;

namespace {

constexpr double kP1Lat = 49.5001, kP1Lon = 17.995;
constexpr double kP3Lat = 49.5002, kP3Lon = 17.995;
constexpr double kP2Lat = 49.4999, kP2Lon = 18.008;
constexpr double kQLat = 49.5, kQLon = 18.0002;
constexpr double kToleranceM = 0.01;

class MapSetTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new rt::TempDir();
    std::filesystem::create_directory(dir_->file("maps"));
    build(rt::osm_node(1, 49.5, 17.990) + rt::osm_node(2, 49.5, 17.9999) +
              rt::osm_way(100, "1 2", "highway=residential;name=West Road"),
          "maps/west.gpkg");
    build(rt::osm_node(3, 49.5, 18.003) + rt::osm_node(4, 49.5, 18.012) +
              rt::osm_way(200, "3 4", "highway=residential;name=East Road"),
          "maps/east.gpkg");
    build(rt::osm_node(5, 49.5003, 17.990) + rt::osm_node(6, 49.5003, 17.9999) +
              rt::osm_way(300, "5 6", "highway=residential;name=North Road"),
          "north.gpkg");
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }

  static void build(const std::string& body, const std::string& name) {
    rp::BuildOptions options;
    // The OSM files stay outside maps/, which must hold maps only.
    options.osm_path = dir_->write(std::filesystem::path(name).filename().string() + ".osm",
                                   rt::osm_document(body));
    options.output_path = dir_->file(name);
    options.tool_version = "test";
    rp::run_build(options);
  }

  static std::string path(const std::string& name) { return dir_->file(name); }

  static MapSet open(const std::vector<std::string>& paths) {
    auto set = MapSet::open(paths);
    EXPECT_TRUE(set.ok()) << set.status.message;
    return std::move(*set.value);
  }

  static rt::TempDir* dir_;
};

rt::TempDir* MapSetTest::dir_ = nullptr;

TEST_F(MapSetTest, TheTwoMapsLieInZones33And34) {
  MapSet set = open({path("maps/west.gpkg"), path("maps/east.gpkg")});
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.map(0).info().zone, (UtmZone{33, true}));
  EXPECT_EQ(set.map(1).info().zone, (UtmZone{34, true}));
}

TEST_F(MapSetTest, EachPositionIsAnsweredByTheMapThatCoversIt) {
  MapSet set = open({path("maps/west.gpkg"), path("maps/east.gpkg")});
  const auto west = set.nearest(Position::wgs84(kP1Lat, kP1Lon));
  ASSERT_TRUE(west.ok()) << west.status.message;
  EXPECT_EQ(west->map.index, 0u);
  EXPECT_EQ(west->map.path, path("maps/west.gpkg"));
  // The id the map carries (roadcross-build writes one), as MapInfo reads it.
  EXPECT_EQ(west->map.map_id, set.map(0).info().map_id);
  EXPECT_EQ(west->map.map_id.size(), 64u);
  EXPECT_EQ(west->answer.osm_way_id, 100);
  EXPECT_NEAR(west->answer.distance_m, 11.1121, kToleranceM);
  // Answered in the map's own grid: zone 33's easting of P1.
  EXPECT_NEAR(west->answer.query.easting_m, 716844.8895, 1e-3);

  const auto east = set.assess(Position::wgs84(kP2Lat, kP2Lon));
  ASSERT_TRUE(east.ok()) << east.status.message;
  EXPECT_EQ(east->map.index, 1u);
  EXPECT_EQ(east->map.path, path("maps/east.gpkg"));
  EXPECT_EQ(east->answer.road.osm_way_id, 200);
  EXPECT_EQ(east->answer.road.name, "East Road");
  EXPECT_NEAR(east->answer.road.distance_m, 11.1335, kToleranceM);
  EXPECT_NEAR(east->answer.road.query.easting_m, 283371.4030, 1e-3);
}

TEST_F(MapSetTest, NearTheBorderTheNearestRoadOfBothMapsDecides) {
  // Q lies in zone 34, but West's road (zone 33) is nearer than East's.
  MapSet set = open({path("maps/east.gpkg"), path("maps/west.gpkg")});
  auto covering = set.covering(Position::wgs84(kQLat, kQLon), 1000.0);
  ASSERT_TRUE(covering.ok()) << covering.status.message;
  EXPECT_EQ(*covering, (std::vector<std::size_t>{0, 1}));
  const auto answer = set.road_heading(Position::wgs84(kQLat, kQLon));
  ASSERT_TRUE(answer.ok()) << answer.status.message;
  EXPECT_EQ(answer->map.path, path("maps/west.gpkg"));
  EXPECT_EQ(answer->answer.road.osm_way_id, 100);
  EXPECT_NEAR(answer->answer.road.distance_m, 21.7349, kToleranceM);
  const auto chosen = set.choose(Position::wgs84(kQLat, kQLon));
  ASSERT_TRUE(chosen.ok()) << chosen.status.message;
  EXPECT_EQ(*chosen, 1u);
  EXPECT_EQ(set.choose(Position::wgs84(kQLat, kQLon), 10.0).status.code, StatusCode::not_found);
  // Within 150 m only East's coverage (grown by 150 m) is out of reach: West alone answers.
  covering = set.covering(Position::wgs84(kQLat, kQLon), 150.0);
  ASSERT_TRUE(covering.ok());
  EXPECT_EQ(*covering, (std::vector<std::size_t>{1}));
  // And within 10 m no map has a road.
  const auto none = set.nearest(Position::wgs84(kQLat, kQLon), 10.0);
  EXPECT_EQ(none.status.code, StatusCode::not_found);
}

TEST_F(MapSetTest, AUtmPositionNeedsItsZone) {
  MapSet set = open({path("maps/west.gpkg"), path("maps/east.gpkg")});
  const auto bare = set.assess(Position::utm(283371.402976411, 5487332.52222129));
  EXPECT_EQ(bare.status.code, StatusCode::invalid_argument);
  EXPECT_NE(bare.status.message.find("zone"), std::string::npos) << bare.status.message;
  // P2 in zone 34 goes to East; the same point in zone 33's grid too (reprojected).
  const auto in34 =
      set.nearest(Position::utm(283371.402976411, 5487332.52222129, UtmZone{34, true}));
  ASSERT_TRUE(in34.ok()) << in34.status.message;
  EXPECT_EQ(in34->map.index, 1u);
  EXPECT_NEAR(in34->answer.distance_m, 11.1335, kToleranceM);
  // Q in zone 33's grid: West's road, 21.73 m.
  const auto in33 =
      set.nearest(Position::utm(717221.770812755, 5487367.26290318, UtmZone{33, true}));
  ASSERT_TRUE(in33.ok()) << in33.status.message;
  EXPECT_EQ(in33->map.index, 0u);
  EXPECT_NEAR(in33->answer.distance_m, 21.7349, kToleranceM);
  // A single Map reprojects a position given in another zone as well.
  auto east = Map::open(path("maps/east.gpkg"));
  ASSERT_TRUE(east.ok());
  const auto reprojected =
      east->nearest(Position::utm(717221.770812755, 5487367.26290318, UtmZone{33, true}));
  ASSERT_TRUE(reprojected.ok()) << reprojected.status.message;
  EXPECT_NEAR(reprojected->distance_m, 202.8586, kToleranceM);
}

TEST_F(MapSetTest, OverlappingMapsTheNearerRoadAnswers) {
  MapSet set = open({path("maps/west.gpkg"), path("north.gpkg")});
  const auto p1 = set.assess(Position::wgs84(kP1Lat, kP1Lon));
  ASSERT_TRUE(p1.ok()) << p1.status.message;
  EXPECT_EQ(p1->map.index, 0u);
  EXPECT_EQ(p1->answer.road.osm_way_id, 100);
  EXPECT_NEAR(p1->answer.road.distance_m, 11.1121, kToleranceM);
  const auto p3 = set.assess(Position::wgs84(kP3Lat, kP3Lon));
  ASSERT_TRUE(p3.ok()) << p3.status.message;
  EXPECT_EQ(p3->map.index, 1u);
  EXPECT_EQ(p3->map.path, path("north.gpkg"));
  EXPECT_EQ(p3->answer.road.osm_way_id, 300);
  EXPECT_NEAR(p3->answer.road.distance_m, 11.1357, kToleranceM);
  const auto better = set.better_place(Position::wgs84(kP3Lat, kP3Lon));
  ASSERT_TRUE(better.ok()) << better.status.message;
  EXPECT_EQ(better->map.index, 1u);
}

TEST_F(MapSetTest, TheSameMapTwiceTheFirstAnswers) {
  MapSet set = open({path("north.gpkg"), path("maps/west.gpkg"), path("maps/west.gpkg")});
  const auto p1 = set.nearest(Position::wgs84(kP1Lat, kP1Lon));
  ASSERT_TRUE(p1.ok()) << p1.status.message;
  EXPECT_EQ(p1->map.index, 1u);
}

TEST_F(MapSetTest, ADirectoryOpensEveryMapInItByName) {
  MapSet set = open({path("maps")});
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.map(0).info().path, path("maps/east.gpkg"));
  EXPECT_EQ(set.map(1).info().path, path("maps/west.gpkg"));
  const auto east = set.nearest(Position::wgs84(kP2Lat, kP2Lon));
  ASSERT_TRUE(east.ok()) << east.status.message;
  EXPECT_EQ(east->map.path, path("maps/east.gpkg"));
}

TEST_F(MapSetTest, ANonMapFileInTheDirectoryIsNamed) {
  rt::TempDir dir;
  std::filesystem::create_directory(dir.file("fleet"));
  std::filesystem::copy_file(path("maps/west.gpkg"), dir.file("fleet/west.gpkg"));
  dir.write("fleet/notes.txt", "not a map\n");
  const auto set = MapSet::open({dir.file("fleet")});
  ASSERT_FALSE(set.ok());
  EXPECT_EQ(set.status.code, StatusCode::not_a_database);
  EXPECT_NE(set.status.message.find(dir.file("fleet/notes.txt")), std::string::npos)
      << set.status.message;
  std::filesystem::create_directory(dir.file("empty"));
  const auto empty = MapSet::open({dir.file("empty")});
  EXPECT_EQ(empty.status.code, StatusCode::file_not_found);
  EXPECT_NE(empty.status.message.find(dir.file("empty")), std::string::npos);
  const auto missing = MapSet::open({path("maps/west.gpkg"), dir.file("nowhere.gpkg")});
  EXPECT_EQ(missing.status.code, StatusCode::file_not_found);
  EXPECT_NE(missing.status.message.find(dir.file("nowhere.gpkg")), std::string::npos);
  EXPECT_EQ(MapSet::open({}).status.code, StatusCode::invalid_argument);
}

TEST_F(MapSetTest, TheCoverageIsStoredAndComputedForOlderMaps) {
  auto stored = Map::open(path("maps/west.gpkg"));
  ASSERT_TRUE(stored.ok());
  const roadcross::MapInfo& info = stored->info();
  EXPECT_TRUE(info.coverage_stored);
  // The grid extent is the road's ends (West A and B above), to the millimetre.
  EXPECT_NEAR(info.min_easting_m, 716483.371, 1e-3);
  EXPECT_NEAR(info.max_easting_m, 717200.053, 1e-3);
  EXPECT_NEAR(info.min_northing_m, 5487337.885, 1e-3);
  EXPECT_NEAR(info.max_northing_m, 5487366.397, 1e-3);
  // The WGS84 box holds the road's ends (lon 17.990..17.9999 at lat 49.5). The road follows the
  // parallel, which the grid shows rising 28.51 m (West's northings) over its length, so the
  // rectangle's corner (min E, max N) lies 28.51 m north of the road and (max E, min N) 28.51 m
  // south: a latitude span of 2 x 28.51 m / 1.0002 (grid scale 3 deg off the central meridian)
  // / 111 198 m per degree (meridian at 49.5 deg) = 5.127e-4 deg, plus the box's 2 x 1e-5.
  EXPECT_TRUE(info.coverage_wgs84.contains(49.5, 17.990));
  EXPECT_TRUE(info.coverage_wgs84.contains(49.5, 17.9999));
  EXPECT_NEAR(info.coverage_wgs84.min_lon_deg, 17.990, 2e-5);
  EXPECT_NEAR(info.coverage_wgs84.max_lon_deg, 17.9999, 2e-5);
  EXPECT_NEAR(info.coverage_wgs84.max_lat_deg - info.coverage_wgs84.min_lat_deg, 5.327e-4, 2e-6);

  // A map written before the coverage keys: the same coverage, computed on open from
  // gpkg_contents.
  rt::TempDir dir;
  const std::string old_map = dir.file("old.gpkg");
  std::filesystem::copy_file(path("maps/west.gpkg"), old_map);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(old_map.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "DELETE FROM roadcross_metadata WHERE key LIKE 'coverage.%'", nullptr,
                         nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  auto computed = Map::open(old_map);
  ASSERT_TRUE(computed.ok()) << computed.status.message;
  const roadcross::MapInfo& old_info = computed->info();
  EXPECT_FALSE(old_info.coverage_stored);
  EXPECT_NEAR(old_info.min_easting_m, info.min_easting_m, 1e-3);
  EXPECT_NEAR(old_info.max_northing_m, info.max_northing_m, 1e-3);
  EXPECT_NEAR(old_info.coverage_wgs84.min_lat_deg, info.coverage_wgs84.min_lat_deg, 1e-9);
  EXPECT_NEAR(old_info.coverage_wgs84.max_lon_deg, info.coverage_wgs84.max_lon_deg, 1e-9);
  MapSet set = open({old_map, path("maps/east.gpkg")});
  const auto west = set.nearest(Position::wgs84(kP1Lat, kP1Lon));
  ASSERT_TRUE(west.ok()) << west.status.message;
  EXPECT_EQ(west->map.path, old_map);
}

}  // namespace
