// The runtime on a DB built from a hand-written map. The road runs from (50.0, 14.399) to
// (50.0, 14.401); in UTM 33N (gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32633) its ends are
//   A = (456928.223997736, 5538803.7545774), B = (457071.556792445, 5538802.60471974)
// so it points east, turned slightly south by the meridian convergence: yaw = atan2(dN, dE).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
using roadcross::Map;
using roadcross::Position;
using roadcross::StatusCode;
using roadcross::geo::kPi;

namespace {

constexpr double kAx = 456928.223997736, kAy = 5538803.7545774;
constexpr double kBx = 457071.556792445, kBy = 5538802.60471974;

class MapQuery : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string osm =
        dir_.write("road.osm",
                   rt::osm_document(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.401) +
                                    rt::osm_node(3, 50.001, 14.4) + rt::osm_node(4, 50.002, 14.4) +
                                    rt::osm_way(10, "1 2", "highway=residential;name=East Street") +
                                    rt::osm_way(20, "3 4", "highway=service")));
    db_path_ = dir_.file("road.gpkg");
    rp::BuildOptions options;
    options.osm_path = osm;
    options.output_path = db_path_;
    options.tool_version = "test";
    rp::run_build(options);
  }

  Map open() {
    auto map = Map::open(db_path_);
    EXPECT_TRUE(map.ok()) << map.status.message;
    return std::move(*map.value);
  }

  // A point at `fraction` along A->B, `offset_m` to the left of the road (north side).
  static Position beside_road(double fraction, double offset_m) {
    const double dx = kBx - kAx, dy = kBy - kAy, length = std::hypot(dx, dy);
    return Position::utm(kAx + fraction * dx - offset_m * dy / length,
                         kAy + fraction * dy + offset_m * dx / length);
  }

  static double road_yaw() { return std::atan2(kBy - kAy, kBx - kAx); }

  rt::TempDir dir_;
  std::string db_path_;
};

TEST_F(MapQuery, OpenReadsTheMetadata) {
  Map map = open();
  EXPECT_EQ(map.info().zone, (roadcross::geo::UtmZone{33, true}));
  EXPECT_EQ(map.info().epsg, 32633);
  EXPECT_EQ(map.info().schema_version, roadcross::schema::kSchemaVersion);
  EXPECT_GT(map.info().segment_count, 15);
  EXPECT_NEAR(map.info().min_easting_m, kAx, 1e-6);
}

TEST_F(MapQuery, NearestAndHeadingNorthAndSouthOfAnEastWestRoad) {
  Map map = open();
  const auto north = map.road_heading(beside_road(0.43, 5.0));
  ASSERT_TRUE(north.ok()) << north.status.message;
  EXPECT_NEAR(north->road.distance_m, 5.0, 1e-6);
  EXPECT_EQ(north->road.osm_way_id, 10);
  EXPECT_EQ(north->road.name, "East Street");
  EXPECT_EQ(north->road.highway, "residential");
  EXPECT_NEAR(north->road_heading_rad, road_yaw(), 1e-9);
  // North of the road, the robot faces south across it: road yaw - pi/2 (about -pi/2).
  EXPECT_NEAR(north->crossing_heading_rad, road_yaw() - kPi / 2, 1e-9);
  EXPECT_NEAR(north->crossing_heading_rad, -kPi / 2, 0.01);
  EXPECT_FALSE(north->on_centreline);

  const auto south = map.road_heading(beside_road(0.43, -5.0));
  ASSERT_TRUE(south.ok());
  EXPECT_NEAR(south->crossing_heading_rad, road_yaw() + kPi / 2, 1e-9);
  EXPECT_NEAR(south->crossing_bearing_deg, 0.0 + roadcross::geo::rad_to_deg(-road_yaw()), 1e-6);
}

TEST_F(MapQuery, NorthSouthRoadFacesEastOrWest) {
  // Way 20 runs north from (50.001, 14.4); a point 3 m east of it crosses westwards (~pi).
  Map map = open();
  const auto p = map.to_utm(Position::wgs84(50.0015, 14.4));
  ASSERT_TRUE(p.ok());
  const auto east = map.road_heading(Position::utm(p->easting_m + 3.0, p->northing_m));
  ASSERT_TRUE(east.ok());
  EXPECT_EQ(east->road.osm_way_id, 20);
  EXPECT_NEAR(east->road.distance_m, 3.0, 0.01);  // the road is within 0.5 deg of grid north
  EXPECT_NEAR(std::abs(east->crossing_heading_rad), kPi, 0.01);
  const auto west = map.road_heading(Position::utm(p->easting_m - 3.0, p->northing_m));
  ASSERT_TRUE(west.ok());
  EXPECT_NEAR(west->crossing_heading_rad, 0.0, 0.01);
}

TEST_F(MapQuery, BeyondTheEndTheClosestPointIsTheEnd) {
  Map map = open();
  const auto road = map.nearest(Position::utm(kAx - 4.0, kAy + 3.0));
  ASSERT_TRUE(road.ok());
  EXPECT_NEAR(road->closest.easting_m, kAx, 1e-6);
  EXPECT_NEAR(road->closest.northing_m, kAy, 1e-6);
  EXPECT_NEAR(road->distance_m, 5.0, 1e-6);
}

TEST_F(MapQuery, AtADeadEndTheHeadingIsTheSegmentsOwn) {
  // Beyond node 1, where way 10 starts and nothing else does.
  Map map = open();
  const auto heading = map.road_heading(Position::utm(kAx - 4.0, kAy + 3.0));
  ASSERT_TRUE(heading.ok());
  EXPECT_NEAR(heading->road_heading_rad, road_yaw(), 1e-9);
}

TEST_F(MapQuery, Wgs84InputEqualsProjectedInput) {
  Map map = open();
  const auto by_latlon = map.nearest(Position::wgs84(50.00004, 14.4003));
  const auto projected = map.to_utm(Position::wgs84(50.00004, 14.4003));
  ASSERT_TRUE(by_latlon.ok() && projected.ok());
  const auto by_utm = map.nearest(Position::utm(projected->easting_m, projected->northing_m));
  ASSERT_TRUE(by_utm.ok());
  EXPECT_EQ(by_latlon->segment_id, by_utm->segment_id);
  EXPECT_DOUBLE_EQ(by_latlon->distance_m, by_utm->distance_m);
}

TEST_F(MapQuery, OnTheCentrelineTheSideIsUnknown) {
  Map map = open();
  const auto on = map.road_heading(beside_road(0.5, 0.0));
  ASSERT_TRUE(on.ok());
  EXPECT_TRUE(on->on_centreline);
  EXPECT_NEAR(on->crossing_heading_rad, road_yaw() - kPi / 2, 1e-9);
}

TEST_F(MapQuery, AnOpenMapBlocksWritesInPlaceAndKeepsReadingAReplacedFile) {
  Map map = open();
  {
    roadcross::sqlite::Database db(db_path_, SQLITE_OPEN_READWRITE);
    try {
      db.exec("UPDATE roadcross_metadata SET value = 'changed' WHERE key = 'tool_version'");
      ADD_FAILURE() << "a write in place succeeded while a Map had the file open";
    } catch (const roadcross::sqlite::sqlite_error& e) {
      EXPECT_EQ(e.code() & 0xff, SQLITE_BUSY) << e.what();
    }
  }
  // roadcross-build writes a new file and renames it over the old one: here a map of way 20
  // only. The open Map still reads the file it opened; a new one reads the new file.
  rp::BuildOptions options;
  options.osm_path = dir_.write(
      "north.osm", rt::osm_document(rt::osm_node(3, 50.001, 14.4) + rt::osm_node(4, 50.002, 14.4) +
                                    rt::osm_way(20, "3 4", "highway=service")));
  options.output_path = db_path_;
  options.tool_version = "test";
  rp::run_build(options);
  const auto before = map.nearest(beside_road(0.43, 5.0));
  ASSERT_TRUE(before.ok()) << before.status.message;
  EXPECT_EQ(before->osm_way_id, 10);
  EXPECT_NEAR(before->distance_m, 5.0, 1e-6);
  Map replaced = open();
  const auto after = replaced.nearest(beside_road(0.43, 5.0));
  ASSERT_TRUE(after.ok()) << after.status.message;
  EXPECT_EQ(after->osm_way_id, 20);
}

TEST_F(MapQuery, BadPositions) {
  Map map = open();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(map.nearest(Position::utm(nan, 5538800.0)).status.code, StatusCode::invalid_argument);
  EXPECT_EQ(map.nearest(Position::wgs84(95.0, 14.4)).status.code, StatusCode::invalid_argument);
  EXPECT_EQ(map.nearest(Position::wgs84(50.0, 200.0)).status.code, StatusCode::invalid_argument);
  EXPECT_EQ(map.road_heading(Position::wgs84(nan, 14.4)).status.code, StatusCode::invalid_argument);
  // 200 m south of the road with a 100 m search radius: not found, with the radius in the message.
  const auto far = map.nearest(beside_road(0.5, -200.0), 100.0);
  EXPECT_EQ(far.status.code, StatusCode::not_found);
  EXPECT_NE(far.status.message.find("100"), std::string::npos);
  EXPECT_TRUE(map.nearest(beside_road(0.5, -200.0), 300.0).ok());
  EXPECT_EQ(map.nearest(beside_road(0.5, 1.0), 0.0).status.code, StatusCode::invalid_argument);
}

TEST_F(MapQuery, OpenErrorsSayWhatToDo) {
  const auto missing = Map::open(dir_.file("missing.gpkg"));
  EXPECT_EQ(missing.status.code, StatusCode::file_not_found);
  EXPECT_NE(missing.status.message.find("missing.gpkg"), std::string::npos);

  const auto text = Map::open(dir_.write("text.gpkg", "this is not a database\n"));
  EXPECT_EQ(text.status.code, StatusCode::not_a_database);
  EXPECT_NE(text.status.message.find("roadcross-build"), std::string::npos);

  {
    roadcross::sqlite::Database plain(dir_.file("plain.sqlite"),
                                      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    plain.exec("CREATE TABLE t (x)");
  }
  EXPECT_EQ(Map::open(dir_.file("plain.sqlite")).status.code, StatusCode::not_a_database);

  {
    roadcross::sqlite::Database db(db_path_, SQLITE_OPEN_READWRITE);
    db.exec("UPDATE roadcross_metadata SET value = '999' WHERE key = 'schema_version'");
  }
  const auto newer = Map::open(db_path_);
  EXPECT_EQ(newer.status.code, StatusCode::wrong_version);
  EXPECT_NE(newer.status.message.find("999"), std::string::npos);
  EXPECT_NE(newer.status.message.find("newer"), std::string::npos);
  {
    roadcross::sqlite::Database db(db_path_, SQLITE_OPEN_READWRITE);
    db.exec("UPDATE roadcross_metadata SET value = '0' WHERE key = 'schema_version'");
  }
  EXPECT_EQ(Map::open(db_path_).status.code, StatusCode::wrong_version);
  {
    roadcross::sqlite::Database db(db_path_, SQLITE_OPEN_READWRITE);
    db.exec("DELETE FROM roadcross_metadata WHERE key = 'utm_zone'");
    db.exec("UPDATE roadcross_metadata SET value = '1' WHERE key = 'schema_version'");
  }
  EXPECT_EQ(Map::open(db_path_).status.code, StatusCode::corrupt_database);
}

// Two segments meeting at a corner. Way 10 runs east from node 1 = A to node 2 at (50.0, 14.4),
// the corner C; way 30 runs north from C to node 3 at (50.001, 14.4), N. Node 4 at
// (50.001, 14.399) is W, north-west of C. In UTM 33N (gdaltransform, as above):
constexpr double kCx = 456999.890393961, kCy = 5538803.17916943;
constexpr double kNx = 457000.782347338, kNy = 5538914.36269954;
constexpr double kWx = 456929.117437783, kWy = 5538914.93810399;
// Directions there: A->C, yaw atan2(-0.5754, 71.6664) = -0.008029; C->N, yaw
// atan2(111.1835, 0.8920) = pi/2 - 0.008022 = 1.562774; their bisector 0.777373 = pi/4 - 0.008025.
const double kEastYaw = std::atan2(kCy - kAy, kCx - kAx);
const double kNorthYaw = std::atan2(kNy - kCy, kNx - kCx);
const double kBisector = 0.5 * (kEastYaw + kNorthYaw);

Map build_map(const rt::TempDir& dir, const std::string& ways) {
  const std::string osm = dir.write(
      "bend.osm",
      rt::osm_document(rt::osm_node(1, 50.0, 14.399) + rt::osm_node(2, 50.0, 14.4) +
                       rt::osm_node(3, 50.001, 14.4) + rt::osm_node(4, 50.001, 14.399) + ways));
  rp::BuildOptions options;
  options.osm_path = osm;
  options.output_path = dir.file("bend.gpkg");
  options.tool_version = "test";
  rp::run_build(options);
  auto map = Map::open(options.output_path);
  EXPECT_TRUE(map.ok()) << map.status.message;
  return std::move(*map.value);
}

// Outside the corner, 2 m east and 2 m south of C: the closest point of both segments is C.
const Position kOutsideTheCorner = Position::utm(kCx + 2.0, kCy - 2.0);

TEST(RoadHeadingAtAVertex, TwoSegmentsMeetingGiveTheBisector) {
  rt::TempDir dir;
  Map map = build_map(dir, rt::osm_way(10, "1 2", "highway=residential") +
                               rt::osm_way(30, "2 3", "highway=residential"));
  const auto heading = map.road_heading(kOutsideTheCorner);
  ASSERT_TRUE(heading.ok()) << heading.status.message;
  EXPECT_NEAR(heading->road.closest.easting_m, kCx, 1e-6);
  EXPECT_NEAR(heading->road.closest.northing_m, kCy, 1e-6);
  EXPECT_NEAR(heading->road.distance_m, 2.0 * std::sqrt(2.0), 1e-6);
  // Whichever of the two segments is reported, the heading is the bisector: north-east.
  EXPECT_NEAR(heading->road_heading_rad, kBisector, 1e-9);
  EXPECT_NEAR(heading->road_heading_rad, 0.777373, 1e-6);
  // South-east of a road heading north-east is its right: cross towards the north-west.
  EXPECT_NEAR(heading->crossing_heading_rad, kBisector + kPi / 2, 1e-9);
}

TEST(RoadHeadingAtAVertex, ASegmentDrawnTheOtherWayIsTurnedAround) {
  // Way 30 drawn from N to C: the road is A->C->N or N->C->A, as the reported segment is drawn.
  rt::TempDir dir;
  Map map = build_map(dir, rt::osm_way(10, "1 2", "highway=residential") +
                               rt::osm_way(30, "3 2", "highway=residential"));
  const auto heading = map.road_heading(kOutsideTheCorner);
  ASSERT_TRUE(heading.ok()) << heading.status.message;
  if (heading->road.osm_way_id == 10) {
    EXPECT_NEAR(heading->road_heading_rad, kBisector, 1e-9);  // north-east
  } else {
    ASSERT_EQ(heading->road.osm_way_id, 30);
    EXPECT_NEAR(heading->road_heading_rad, kBisector - kPi, 1e-9);  // south-west, -2.364220
  }
}

TEST(RoadHeadingAtAVertex, AtAJunctionTheSegmentKeepsItsOwnDirection) {
  // Way 40 from C to W makes C a junction of three segments: no one continuation, so the
  // reported segment's own direction, whichever of the three it is (all end at C).
  rt::TempDir dir;
  Map map = build_map(dir, rt::osm_way(10, "1 2", "highway=residential") +
                               rt::osm_way(30, "2 3", "highway=residential") +
                               rt::osm_way(40, "2 4", "highway=residential"));
  const auto heading = map.road_heading(kOutsideTheCorner);
  ASSERT_TRUE(heading.ok()) << heading.status.message;
  EXPECT_NEAR(heading->road.distance_m, 2.0 * std::sqrt(2.0), 1e-6);
  switch (heading->road.osm_way_id) {
    case 10:
      EXPECT_NEAR(heading->road_heading_rad, kEastYaw, 1e-9);
      break;
    case 30:
      EXPECT_NEAR(heading->road_heading_rad, kNorthYaw, 1e-9);
      break;
    case 40:  // C->W: atan2(111.7589, -70.7730) = 2.135317
      EXPECT_NEAR(heading->road_heading_rad, std::atan2(kWy - kCy, kWx - kCx), 1e-9);
      EXPECT_NEAR(heading->road_heading_rad, 2.135317, 1e-6);
      break;
    default:
      ADD_FAILURE() << "unexpected way " << heading->road.osm_way_id;
  }
}

}  // namespace
