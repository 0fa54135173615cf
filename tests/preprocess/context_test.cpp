// The context stage on tests/data/context_tags.osm, a hand-written map with one road per tag
// form and one node per crossing kind. Every expected value below is derived by hand from the
// tag, the national table (CZ: the map's speed tags are mostly CZ:*) and the thesis' points
// (docs/cost-model.md):
//   speed <=30 -> 3, <=50 -> 2, <=80 -> 1; lanes 1..4 -> 5, 4, 2, 1; width <=3.5/4.5/5.5/6.5 ->
//   4/3/2/1; residential, living_street, service 3, primary 1, trunk -4, motorway -10;
//   defaults: two-way residential 2 lanes, width = lanes x 3.0 m (x 3.5 m on major roads).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/context/context.hpp"
#include "roadcross/preprocess/context/crossings.hpp"
#include "roadcross/preprocess/graph/segments.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;

namespace {

const std::string kMap = std::string(ROADCROSS_TEST_DATA_DIR) + "/context_tags.osm";

struct Built {
  rp::RoadNetwork network;
  rp::RoadGraph graph;
  rp::ContextReport report;
};

const Built& built() {
  static const Built b = [] {
    Built out;
    rp::Progress progress(false);
    out.network = rp::read_road_network(kMap, progress);
    out.graph = rp::build_road_graph(out.network, rp::choose_utm_zone(out.network), 10.0);
    out.report = rp::compute_context(out.graph, out.network, rp::ContextParameters{}, "", {});
    return out;
  }();
  return b;
}

const rp::Segment& first_segment_of(std::int64_t way_id) {
  for (const rp::Segment& s : built().graph.segments) {
    if (built().graph.osm_way_id(s) == way_id) return s;
  }
  throw std::runtime_error("no segment of way " + std::to_string(way_id));
}

struct Expected {
  std::int64_t way;
  double maxspeed_kmh;
  int lanes;
  double width_m;
  int context;
  const char* defaulted;  // "" = none
};

// way: tag(s) -> maxspeed, lanes, width, context, defaulted.
const Expected kExpected[] = {
    {1, 50, 2, 6.0, 10, "lanes,width"},             // maxspeed=50: 2+4+1+3
    {2, 50, 2, 6.0, 10, "lanes,width"},             // "50 km/h"
    {3, 30 * 1.609344, 2, 6.0, 10, "lanes,width"},  // "30 mph" = 48.28 km/h
    {4, 50, 2, 6.0, 10, "lanes,width"},             // CZ:urban (361/2000 s.18(4))
    {5, 90, 2, 6.0, 8, "lanes,width"},              // CZ:rural: 0+4+1+3
    {6, 130, 2, 6.0, 8, "lanes,width"},             // CZ:motorway
    {7, 20, 2, 6.0, 11, "lanes,width"},             // CZ:living_street: 3+4+1+3
    {8, 50, 2, 6.0, 10, "lanes,width"},             // DE:urban
    {9, 100, 2, 6.0, 8, "lanes,width"},             // DE:rural
    {10, 30, 2, 6.0, 11, "lanes,width"},            // DE:zone30
    {11, 7, 2, 6.0, 11, "lanes,width"},             // walk = 7 km/h
    {12, 200, 2, 6.0, 8, "lanes,width"},            // none = kNoLimitKmh
    {13, 50, 2, 6.0, 10, "maxspeed,lanes,width"},   // signals -> CZ:urban default
    {14, 50, 2, 6.0, 10, "lanes,width"},            // "50;30" -> the higher
    {15, 70, 2, 6.0, 9, "lanes,width"},             // forward 50 / backward 70: 1+4+1+3
    {16, 90, 2, 6.0, 8, "lanes,width"},             // source:maxspeed=CZ:rural
    {17, 30, 2, 6.0, 11, "lanes,width"},            // zone:maxspeed=DE:30
    {18, 50, 2, 6.0, 10, "maxspeed,width"},         // lanes=2
    {19, 50, 3, 9.0, 7, "maxspeed,width"},          // lanes=2;3 -> 3: 2+2+0+3
    {20, 50, 3, 9.0, 7, "maxspeed,width"},          // lanes:forward 2 + backward 1
    {21, 50, 1, 3.0, 14, "maxspeed,lanes,width"},   // oneway: 1 lane, 3 m: 2+5+4+3
    {22, 50, 2, 7.0, 7, "maxspeed,lanes,width"},    // primary: 2 x 3.5 m: 2+4+0+1
    {23, 50, 2, 6.0, 10, "maxspeed,lanes"},         // width=6
    {24, 50, 2, 6.0, 10, "maxspeed,lanes"},         // "6 m"
    {25, 50, 2, 6.5, 10, "maxspeed,lanes"},         // "6.5m"
    {26, 50, 2, 6.5, 10, "maxspeed,lanes"},         // "6,5"
    {27, 50, 2, 6.096, 10, "maxspeed,lanes"},       // 20' = 6.096 m
    {28, 50, 2, 6.096, 10, "maxspeed,lanes"},       // "20 ft"
    {29, 50, 2, 4.0, 12, "maxspeed,lanes"},         // est_width=4: 2+4+3+3
    {30, 50, 2, 6.0, 10, "maxspeed,lanes,width"},   // maxspeed=fast: not understood
    {31, 130, 2, 7.0, -6, "maxspeed,lanes,width"},  // motorway oneway: 0+4+0-10
    {32, 50, 4, 14.0, -1, "maxspeed,lanes,width"},  // trunk (urban): 2+1+0-4
    {33, 20, 1, 3.0, 15, "maxspeed,lanes,width"},   // living_street: 3+5+4+3
    {34, 50, 1, 3.0, 14, "maxspeed,lanes,width"},   // service: 2+5+4+3
};

TEST(ContextStage, EveryTagFormGivesTheHandDerivedValues) {
  for (const Expected& e : kExpected) {
    SCOPED_TRACE("way " + std::to_string(e.way));
    const rp::Segment& s = first_segment_of(e.way);
    // Segments store these as floats (7 digits): 30 mph = 48.28032 km/h reads 48.280319.
    EXPECT_NEAR(*built().graph.maxspeed_kmh(s), e.maxspeed_kmh, 1e-5);
    EXPECT_EQ(*built().graph.lanes(s), e.lanes);
    EXPECT_NEAR(*built().graph.width_m(s), e.width_m, 1e-5);
    EXPECT_EQ(*s.context_score, e.context);
    const std::string* defaulted = built().graph.context_defaulted(s);
    EXPECT_EQ(defaulted ? *defaulted : std::string(), e.defaulted);
    const bool busy = s.reasons.contains("BUSY_ROAD");
    EXPECT_EQ(busy, e.context < 5);
  }
}

TEST(ContextStage, CountryFromTagsAndSummaryCounts) {
  const rp::ContextReport& r = built().report;
  EXPECT_EQ(r.country.country, "CZ");  // 5 CZ:* tags against 4 DE:*
  EXPECT_EQ(r.country.how, "tags");
  EXPECT_EQ(r.unparsed_ways.at("maxspeed"), 2u);  // w13 signals, w30 fast
  EXPECT_EQ(r.unparsed_ways.count("lanes"), 0u);
  // maxspeed defaulted: w13 and w18..w34 (18 tag-form ways) and the 5 crossing roads
  // (w100, w200, w201, w202, w203); crossing ways are not roads.
  EXPECT_EQ(r.defaulted_ways.at("maxspeed"), 18u + 5u);
  EXPECT_EQ(r.road_ways, 34u + 5u);
}

struct ExpectedCrossing {
  const char* osm_type;
  std::int64_t osm_id;
  const char* type;
  bool signals;
  bool designated;
};

TEST(ContextStage, EveryCrossingKind) {
  const ExpectedCrossing expected[] = {
      {"node", 1002, "zebra", false, true},
      {"node", 1003, "marked", false, true},
      {"node", 1004, "uncontrolled", false, true},
      {"node", 1005, "traffic_signals", true, true},
      {"node", 1006, "unmarked", false, true},
      {"node", 1007, "informal", false, false},
      {"node", 1008, "marked", false, true},          // crossing:markings=zebra only
      {"node", 1009, "traffic_signals", true, true},  // crossing:signals=yes
      {"node", 1010, "pelican", true, true},          // crossing_ref=pelican
      {"node", 1011, "no", false, false},             // crossing=no
      {"node", 1012, "unspecified", false, true},     // highway=crossing alone
      {"node", 2002, "zebra", false, true},
      {"node", 2022, "informal", false, false},
      {"node", 2033, "unspecified", false, true},   // also on footway=crossing w302
      {"way", 300, "zebra", false, true},           // shares untagged node 2032 with w203
      {"way", 301, "traffic_signals", true, true},  // crosses w203 without a shared node
  };
  const auto& crossings = built().report.crossings;
  ASSERT_EQ(crossings.size(), std::size(expected));  // 3032 on w303 touches no road: absent
  for (std::size_t i = 0; i < crossings.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(crossings[i].osm_type, expected[i].osm_type);
    EXPECT_EQ(crossings[i].osm_id, expected[i].osm_id);
    EXPECT_EQ(crossings[i].kind.type, expected[i].type);
    EXPECT_EQ(crossings[i].kind.signals, expected[i].signals);
    EXPECT_EQ(crossings[i].kind.designated, expected[i].designated);
  }
  // w301 crosses w203 at lon 14.0015, between nodes 2033 and 2034: half way along that edge.
  const rp::Crossing& geometric = crossings.back();
  const rp::Segment& on =
      built().graph.segments[static_cast<std::size_t>(geometric.segment_id - 1)];
  EXPECT_EQ(built().graph.osm_way_id(on), 203);
  const auto& piece = built().graph.pieces[geometric.piece_index];
  EXPECT_NEAR(geometric.offset_in_piece_m, 0.75 * piece.length_m, 0.05);
}

// w200 runs A(14.000000) - B(14.000207, zebra) - C(14.000551), w201 C - D(14.000956), all at
// lat 49.99. One degree of longitude there is 71.70 km on the ellipsoid, x 0.99966 UTM scale
// (zone 33, 1 degree off the central meridian) = 71.67 km: AB = 14.84 m, AC = 39.49 m (four
// 9.87 m segments, midpoints 4.94, 14.81, 24.68, 34.56), CD = 29.03 m (three 9.68 m segments).
TEST(ContextStage, CrossingDistanceAlongTheRoadGraph) {
  std::vector<double> w200, w201;
  std::vector<int> w200_score;
  for (const rp::Segment& s : built().graph.segments) {
    const std::int64_t way = built().graph.osm_way_id(s);
    if (way == 200) w200.push_back(*s.crossing_distance_m), w200_score.push_back(*s.context_score);
    if (way == 201) w201.push_back(*s.crossing_distance_m);
  }
  ASSERT_EQ(w200.size(), 4u);
  ASSERT_EQ(w201.size(), 3u);
  const double expected200[] = {9.90, 0.03, 9.84, 19.72};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(w200[i], expected200[i], 0.1) << i;
  // Past C along w201: BC = 24.65 m plus 4.84, 14.52, 24.19.
  const double expected201[] = {29.49, 39.17, 48.84};
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(w201[i], expected201[i], 0.1) << i;
  // The +10 bonus only within 5 m: the second segment alone (residential base 10).
  EXPECT_EQ(w200_score, (std::vector<int>{10, 20, 10, 10}));
}

TEST(ContextStage, InformalCrossingGivesNoBonusAndNoDistance) {
  for (const rp::Segment& s : built().graph.segments) {
    if (built().graph.osm_way_id(s) != 202) continue;
    EXPECT_FALSE(s.crossing_distance_m.has_value());
    EXPECT_EQ(*s.context_score, 10);
  }
}

TEST(ContextStage, ParametersChangeTheScore) {
  rp::ContextParameters p;
  p.crossing_points = 100;  // thesis code
  p.motorway_points = -50;
  EXPECT_EQ(rp::context_score(130, 2, 7.0, "motorway", false, p), 4 - 50);
  EXPECT_EQ(rp::context_score(50, 2, 6.0, "residential", true, p), 10 + 100);
  EXPECT_EQ(rp::context_score(50, 5, 20.0, "primary_link", false, p), 2 + 0 + 0 + 1);
}

TEST(ContextStage, CrossingsTableInTheGeoPackage) {
  rt::TempDir dir;
  rp::BuildOptions options;
  options.osm_path = kMap;
  options.output_path = dir.file("context.gpkg");
  options.tool_version = "test";
  const rp::BuildSummary summary = rp::run_build(options);
  EXPECT_EQ(summary.crossings, 16u);
  roadcross::sqlite::Database db(options.output_path, SQLITE_OPEN_READONLY);
  const auto scalar = [&](const std::string& sql) {
    auto q = db.prepare(sql);
    EXPECT_TRUE(q.step()) << sql;
    return q.column_text(0);
  };
  EXPECT_EQ(scalar("SELECT count(*) FROM crossings"), "16");
  EXPECT_EQ(scalar("SELECT count(*) FROM rtree_crossings_geom"), "16");
  EXPECT_EQ(
      scalar("SELECT geometry_type_name FROM gpkg_geometry_columns WHERE table_name = 'crossings'"),
      "POINT");
  EXPECT_EQ(scalar("SELECT srs_id FROM gpkg_contents WHERE table_name = 'crossings'"), "32633");
  EXPECT_EQ(
      scalar("SELECT signals || designated || crossing_type FROM crossings WHERE osm_id = 1010"),
      "11pelican");
  // Each crossing's segment is on the road it lies on.
  EXPECT_EQ(scalar("SELECT s.osm_way_id FROM crossings c JOIN segments s ON s.fid = c.segment_id "
                   "WHERE c.osm_id = 1002"),
            "100");
  EXPECT_EQ(scalar("SELECT value FROM roadcross_metadata WHERE key = 'context_country'"), "CZ");
  EXPECT_EQ(scalar("SELECT count(*) FROM segments WHERE context_score IS NULL"), "0");
}

}  // namespace

TEST(ContextStage, SidewalkWaysOnManyPiecesGiveEachItsOwnSides) {
  // 600 parallel east-west roads 111 m apart (several of the per-piece search's chunks), each
  // with a separately mapped sidewalk 6 m north (left), south (right), both or neither, in turn.
  rp::RoadNetwork network;
  constexpr int kRoads = 600;
  constexpr double kSidewalkDeg = 6.0 / 111'195.0;  // 6 m of latitude
  std::vector<rp::NodeLocation> sidewalk_nodes;
  for (int r = 0; r < kRoads; ++r) {
    const double lat = 50.0 + 0.001 * r;
    const std::int64_t a = 1'000'000 + 2 * r, b = a + 1;
    network.ways.push_back({100 + r, "residential", {{"highway", "residential"}}, {a, b}});
    network.locations.push_back({a, lat, 14.0});
    network.locations.push_back({b, lat, 14.0009});
    for (const int side : {1, -1}) {
      if (!(r % 4 == 3 || r % 4 == (side == 1 ? 1 : 2))) continue;
      const std::int64_t s = 2'000'000 + 4 * r + (side == 1 ? 0 : 2);
      sidewalk_nodes.push_back({s, lat + side * kSidewalkDeg, 13.9999});
      sidewalk_nodes.push_back({s + 1, lat + side * kSidewalkDeg, 14.0010});
      network.sidewalk_ways.push_back({5000 + 2 * r + (side == 1 ? 0 : 1), {s, s + 1}});
    }
  }
  network.crossing_way_locations = sidewalk_nodes;
  rp::RoadGraph graph = rp::build_road_graph(network, rp::choose_utm_zone(network), 10.0);
  ASSERT_EQ(graph.pieces.size(), static_cast<std::size_t>(kRoads));
  rp::assign_sidewalks(graph, network, 8.0);
  for (const rp::RoadPiece& piece : graph.pieces) {
    const int r = static_cast<int>(piece.osm_way_id - 100);
    const bool left = r % 4 == 1 || r % 4 == 3, right = r % 4 == 2 || r % 4 == 3;
    EXPECT_EQ(piece.sidewalks.left, left ? std::optional<bool>(true) : std::nullopt) << r;
    EXPECT_EQ(piece.sidewalks.right, right ? std::optional<bool>(true) : std::nullopt) << r;
  }
}
