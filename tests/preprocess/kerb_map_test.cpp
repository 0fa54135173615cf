// Kerbs, refuge islands and pavements from a hand-written map (tests/data/kerbs.osm, its
// comment describes it) through the build into the DB and out of the runtime: the columns, the
// robot's answers on both sides of the road, better_place, the map profile's kerb capability,
// gap_crossing's stages and an older DB without the columns.
//
// The roads run east (left = north, right = south). 1e-5 degrees of latitude are 1.11 m, so
// the positions below stand 3.3 m north or south of a centreline at the crossing's longitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "osm_fixture.hpp"
#include "roadcross/gap.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/runtime.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;
using roadcross::AssessOptions;
using roadcross::Map;
using roadcross::Position;

namespace {

const std::string kOsm = std::string(ROADCROSS_TEST_DATA_DIR) + "/kerbs.osm";

// At the crossing of road A (way 10, lat 50.000), north (left) and south (right) of it.
const Position kNorthOfA = Position::wgs84(50.00003, 14.4);
const Position kSouthOfA = Position::wgs84(49.99997, 14.4);
// Road A far from its crossing (no kerb tagged within 5 m).
const Position kNorthOfAWest = Position::wgs84(50.00003, 14.3993);
// Road B (way 11, lat 50.001), road C (way 12, lat 50.002).
const Position kNorthOfB = Position::wgs84(50.00103, 14.4);
const Position kSouthOfB = Position::wgs84(50.00097, 14.4005);
const Position kNorthOfC = Position::wgs84(50.00203, 14.4005);
const Position kSouthOfC = Position::wgs84(50.00197, 14.4005);

std::string build(const rt::TempDir& dir, double max_kerb_height_m = 1.0) {
  rp::BuildOptions options;
  options.osm_path = kOsm;
  options.output_path = dir.file("kerbs.gpkg");
  options.tool_version = "test";
  options.parameters.suitability.max_kerb_height_m = max_kerb_height_m;
  rp::run_build(options);
  return options.output_path;
}

class KerbMap : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new rt::TempDir;
    path_ = new std::string(build(*dir_));
  }
  static void TearDownTestSuite() {
    delete path_;
    delete dir_;
  }
  Map open() {
    auto map = Map::open(*path_);
    EXPECT_TRUE(map.ok()) << map.status.message;
    return std::move(*map.value);
  }
  static bool has(const std::vector<std::string>& codes, const std::string& code) {
    return std::find(codes.begin(), codes.end(), code) != codes.end();
  }
  // Every threshold met: whether a place is suitable then depends on the forbidding rules.
  static AssessOptions any_score(std::optional<double> max_kerb_height_m = std::nullopt) {
    AssessOptions o;
    o.threshold = -1000;
    o.max_kerb_height_m = max_kerb_height_m;
    return o;
  }
  static rt::TempDir* dir_;
  static std::string* path_;
};
rt::TempDir* KerbMap::dir_ = nullptr;
std::string* KerbMap::path_ = nullptr;

TEST_F(KerbMap, TheColumnsHoldTheTags) {
  roadcross::sqlite::Database db(*path_, SQLITE_OPEN_READONLY);
  // Road A: the crossing segment only (its neighbours' midpoints are 9.56 m away, beyond the
  // 5 m reach): the highest kerb of node 5 (lowered, 0.03), node 6 (lowered but measured
  // 12 cm: 0.12) and node 7 (lowered, 0.03), and the island.
  auto rows = db.prepare(
      "SELECT osm_way_id, kerb, kerb_height_m, crossing_island FROM segments WHERE kerb IS NOT "
      "NULL OR kerb_height_m IS NOT NULL OR crossing_island IS NOT NULL ORDER BY fid");
  ASSERT_TRUE(rows.step());
  EXPECT_EQ(rows.column_int64(0), 10);
  EXPECT_EQ(rows.column_text(1), "lowered");
  EXPECT_DOUBLE_EQ(rows.column_double(2), 0.12);
  EXPECT_EQ(rows.column_int64(3), 1);
  // Road B: the flush kerb where a footway meets it, no island tagged.
  ASSERT_TRUE(rows.step());
  EXPECT_EQ(rows.column_int64(0), 11);
  EXPECT_EQ(rows.column_text(1), "flush");
  EXPECT_DOUBLE_EQ(rows.column_double(2), 0.0);
  EXPECT_TRUE(rows.column_is_null(3));
  EXPECT_FALSE(rows.step());
  // Pavements per way (left, right; -1 for NULL): A sidewalk=right; B the footway=sidewalk
  // 4 m south (right), left unknown; C sidewalk=both with sidewalk:left=no.
  auto sides = db.prepare(
      "SELECT osm_way_id, count(*), min(coalesce(sidewalk_left, -1)), "
      "max(coalesce(sidewalk_left, -1)), min(coalesce(sidewalk_right, -1)), "
      "max(coalesce(sidewalk_right, -1)) FROM segments GROUP BY osm_way_id ORDER BY osm_way_id");
  const int expected[3][3] = {{10, 0, 1}, {11, -1, 1}, {12, 0, 1}};
  for (const auto& e : expected) {
    ASSERT_TRUE(sides.step());
    EXPECT_EQ(sides.column_int64(0), e[0]);
    EXPECT_EQ(sides.column_int64(1), 15);  // 143 m in parts of at most 10 m
    EXPECT_EQ(sides.column_int64(2), e[1]) << "way " << e[0];
    EXPECT_EQ(sides.column_int64(3), e[1]) << "way " << e[0];
    EXPECT_EQ(sides.column_int64(4), e[2]) << "way " << e[0];
    EXPECT_EQ(sides.column_int64(5), e[2]) << "way " << e[0];
  }
  // tactile_paving=yes alone on road C's node 23: a designated crossing.
  auto crossing = db.prepare("SELECT designated FROM crossings WHERE osm_id = 23");
  ASSERT_TRUE(crossing.step());
  EXPECT_EQ(crossing.column_int64(0), 1);
}

TEST_F(KerbMap, AKerbHigherThanTheRobotClimbsForbids) {
  Map map = open();
  auto low = map.assess(kNorthOfA, any_score(0.11));
  ASSERT_TRUE(low.ok()) << low.status.message;
  EXPECT_EQ(*low->kerb, "lowered");
  EXPECT_DOUBLE_EQ(*low->kerb_height_m, 0.12);
  EXPECT_TRUE(*low->crossing_island);
  EXPECT_TRUE(has(low->reasons, "KERB_TOO_HIGH"));
  EXPECT_FALSE(low->suitable);
  // 0.12 m climbs a 0.12 m kerb.
  auto enough = map.assess(kNorthOfA, any_score(0.12));
  EXPECT_FALSE(has(enough->reasons, "KERB_TOO_HIGH"));
  EXPECT_TRUE(enough->suitable) << enough->reasons.size();
  // Without a capability the map's (1 m, no limit) applies.
  auto none = map.assess(kNorthOfA, any_score());
  EXPECT_DOUBLE_EQ(none->max_kerb_height_m, 1.0);
  EXPECT_TRUE(none->suitable);
}

TEST_F(KerbMap, UnknownNeverForbidsAndFlushIsZero) {
  Map map = open();
  auto unknown = map.assess(kNorthOfAWest, any_score(0.0));
  ASSERT_TRUE(unknown.ok());
  EXPECT_FALSE(unknown->kerb);
  EXPECT_FALSE(unknown->kerb_height_m);
  EXPECT_FALSE(has(unknown->reasons, "KERB_TOO_HIGH"));
  EXPECT_TRUE(unknown->suitable);
  auto flush = map.assess(kNorthOfB, any_score(0.0));
  EXPECT_EQ(*flush->kerb, "flush");
  EXPECT_FALSE(has(flush->reasons, "KERB_TOO_HIGH"));
}

TEST_F(KerbMap, TheFarSideIsTheOneAcrossFromTheRobot) {
  Map map = open();
  // Road A has a pavement on its right (south) only.
  auto north = map.assess(kNorthOfA, any_score());
  EXPECT_EQ(north->robot_side, 1);
  EXPECT_TRUE(*north->pavement_far_side);
  EXPECT_FALSE(has(north->reasons, "NO_PAVEMENT_FAR_SIDE"));
  auto south = map.assess(kSouthOfA, any_score());
  EXPECT_EQ(south->robot_side, -1);
  EXPECT_FALSE(*south->pavement_far_side);
  EXPECT_TRUE(has(south->reasons, "NO_PAVEMENT_FAR_SIDE"));
  EXPECT_FALSE(south->suitable);
  // Road B: the south pavement is a separate footway; the north side is unknown.
  EXPECT_TRUE(*map.assess(kNorthOfB, any_score())->pavement_far_side);
  auto south_b = map.assess(kSouthOfB, any_score());
  EXPECT_FALSE(south_b->pavement_far_side);
  EXPECT_TRUE(south_b->suitable);
  // Road C: sidewalk=both, sidewalk:left=no.
  EXPECT_TRUE(*map.assess(kNorthOfC, any_score())->pavement_far_side);
  EXPECT_TRUE(has(map.assess(kSouthOfC, any_score())->reasons, "NO_PAVEMENT_FAR_SIDE"));
  // On the centreline the side is unknown: assess_segment never says NO_PAVEMENT_FAR_SIDE.
  auto segment = map.assess_segment(south->road.segment_id, any_score());
  EXPECT_EQ(segment->robot_side, 0);
  EXPECT_FALSE(has(segment->reasons, "NO_PAVEMENT_FAR_SIDE"));
}

TEST_F(KerbMap, BetterPlaceHonoursBoth) {
  Map map = open();
  roadcross::BetterPlaceOptions options;
  options.assess = any_score(0.11);
  options.max_candidates = 30;
  const std::int64_t crossing_segment = map.assess(kNorthOfA, any_score())->road.segment_id;
  // From the north side, 50 m west of the crossing: the crossing's segment is offered but not
  // suitable with a 0.11 m capability (after every suitable place), suitable with 0.2 m.
  const auto at_crossing = [&](const roadcross::BetterPlaces& places) {
    const auto it = std::find_if(places.candidates.begin(), places.candidates.end(),
                                 [&](const auto& c) { return c.segment_id == crossing_segment; });
    EXPECT_NE(it, places.candidates.end());
    return it == places.candidates.end() ? roadcross::Candidate{} : *it;
  };
  auto low = map.better_place(Position::wgs84(50.00003, 14.3993), options);
  ASSERT_TRUE(low.ok()) << low.status.message;
  ASSERT_TRUE(low->candidates.front().suitable);
  const roadcross::Candidate too_high = at_crossing(*low);
  EXPECT_FALSE(too_high.suitable);
  EXPECT_TRUE(has(too_high.reasons, "KERB_TOO_HIGH"));
  EXPECT_FALSE(has(too_high.reasons, "NO_PAVEMENT_FAR_SIDE"));
  options.assess = any_score(0.2);
  auto high = map.better_place(Position::wgs84(50.00003, 14.3993), options);
  EXPECT_TRUE(at_crossing(*high).suitable);
  // From the south side every place leads to the north side, which has no pavement.
  auto south = map.better_place(Position::wgs84(49.99997, 14.3993), options);
  EXPECT_TRUE(south->candidates.empty());
  EXPECT_FALSE(south->reason.empty());
}

TEST_F(KerbMap, TheRefugeIslandMakesTwoStages) {
  Map map = open();
  auto kerb = roadcross::gap_crossing(map, kNorthOfA);
  ASSERT_TRUE(kerb.ok()) << kerb.status.message;
  EXPECT_TRUE(kerb->refuge_island);
  EXPECT_EQ(kerb->stage, 1);  // 3.3 m from the centreline of a 6 m road: at the kerb
  // 1.1 m from the centreline, within a quarter of the width (1.5 m): on the island.
  auto island = roadcross::gap_crossing(map, Position::wgs84(50.00001, 14.4));
  EXPECT_EQ(island->stage, 2);
  auto elsewhere = roadcross::gap_crossing(map, kNorthOfAWest);
  EXPECT_FALSE(elsewhere->refuge_island);
}

TEST(KerbProfile, TheMapProfilesCapabilityIsTheDefault) {
  rt::TempDir dir;
  auto map = Map::open(build(dir, 0.05));
  ASSERT_TRUE(map.ok());
  AssessOptions options;
  options.threshold = -1000;
  auto profile = map->assess(kNorthOfA, options);
  EXPECT_DOUBLE_EQ(profile->max_kerb_height_m, 0.05);
  EXPECT_TRUE(std::count(profile->reasons.begin(), profile->reasons.end(), "KERB_TOO_HIGH"));
  options.max_kerb_height_m = 0.2;  // the call's capability wins
  EXPECT_TRUE(map->assess(kNorthOfA, options)->suitable);
  options.max_kerb_height_m = -0.1;
  EXPECT_EQ(map->assess(kNorthOfA, options).status.code, roadcross::StatusCode::invalid_argument);
}

TEST(KerbOldDb, ASchemaVersion2DbReadsUnknown) {
  rt::TempDir dir;
  const std::string path = build(dir);
  {
    // What a version 2 DB is: the same without the five columns.
    roadcross::sqlite::Database db(path, SQLITE_OPEN_READWRITE);
    for (const char* column :
         {"kerb", "kerb_height_m", "crossing_island", "sidewalk_left", "sidewalk_right"}) {
      db.exec(std::string("ALTER TABLE segments DROP COLUMN ") + column);
    }
    db.exec("UPDATE roadcross_metadata SET value = '2' WHERE key = 'schema_version'");
  }
  auto map = Map::open(path);
  ASSERT_TRUE(map.ok()) << map.status.message;
  AssessOptions strict;
  strict.threshold = -1000;
  strict.max_kerb_height_m = 0.0;  // a version 3 DB would forbid both here
  auto a = map->assess(kSouthOfA, strict);
  ASSERT_TRUE(a.ok()) << a.status.message;
  EXPECT_FALSE(a->kerb_height_m);
  EXPECT_FALSE(a->pavement_far_side);
  EXPECT_TRUE(a->suitable);
  roadcross::BetterPlaceOptions options;
  options.assess.threshold = -1000;
  EXPECT_TRUE(map->better_place(kSouthOfA, options).ok());
}

}  // namespace
