// Operator overrides: a polygon and a way id applied to tests/data/context_tags.osm (way N is
// the 2-node road at lat 50.000 + 0.001 N, lon 14.000..14.001), and every kind of bad feature.
#include <gtest/gtest.h>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/build.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/context/overrides.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace rp = roadcross::preprocess;
namespace rt = roadcross::testing;

namespace {

const std::string kMap = std::string(ROADCROSS_TEST_DATA_DIR) + "/context_tags.osm";

std::string collection(const std::string& features) {
  return R"({"type": "FeatureCollection", "features": [)" + features + "]}";
}

// A box over the west 40 % of way 1 (lat 50.001): lon 13.9995..14.0004, lat 50.0005..50.0015.
const std::string kSchool = R"({"type": "Feature",
  "geometry": {"type": "Polygon", "coordinates": [[[13.9995, 50.0005], [14.0004, 50.0005],
      [14.0004, 50.0015], [13.9995, 50.0015], [13.9995, 50.0005]]]},
  "properties": {"context_delta": -5, "no_crossing": true, "note": "school entrance"}})";
const std::string kDriveway = R"({"type": "Feature", "geometry": null,
  "properties": {"osm_way_id": [2], "force_suitable": true}})";

std::string error_of(const std::string& feature) {
  try {
    rp::parse_overrides(collection(feature), "o.geojson");
  } catch (const rp::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Overrides, PolygonAndWayIdInTheDatabase) {
  rt::TempDir dir;
  rp::BuildOptions options;
  options.osm_path = kMap;
  options.output_path = dir.file("o.gpkg");
  options.overrides_path = dir.write("o.geojson", collection(kSchool + "," + kDriveway));
  options.tool_version = "test";
  rp::run_build(options);
  roadcross::sqlite::Database db(options.output_path, SQLITE_OPEN_READONLY);
  auto q = db.prepare(
      "SELECT osm_way_id, count(*), sum(override_no_crossing), sum(override_force_suitable), "
      "min(context_score), max(context_score), group_concat(DISTINCT override_note), "
      "sum(reasons LIKE '%OVERRIDE%') FROM segments WHERE override_note IS NOT NULL "
      "GROUP BY osm_way_id ORDER BY osm_way_id");
  // Way 1 (71.67 m, 8 segments of 8.96 m): the box reaches lon 14.0004 = 28.67 m along it, into
  // segment 4 (26.88..35.84 m): segments 1-4 touch it. Base context 10, -5 = 5.
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.column_int64(0), 1);
  EXPECT_EQ(q.column_int64(1), 4);
  EXPECT_EQ(q.column_int64(2), 4);
  EXPECT_EQ(q.column_int64(3), 0);
  EXPECT_EQ(q.column_int64(4), 5);
  EXPECT_EQ(q.column_int64(5), 5);
  EXPECT_EQ(q.column_text(6), "school entrance");
  EXPECT_EQ(q.column_int64(7), 4);
  // Way 2: every segment, force_suitable, the default note.
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.column_int64(0), 2);
  EXPECT_EQ(q.column_int64(1), 8);
  EXPECT_EQ(q.column_int64(2), 0);
  EXPECT_EQ(q.column_int64(3), 8);
  EXPECT_EQ(q.column_int64(4), 10);
  EXPECT_EQ(q.column_text(6), "override feature 1");
  EXPECT_FALSE(q.step());
}

TEST(Overrides, MultiPolygonAndBothSelectors) {
  const auto o = rp::parse_overrides(collection(R"({"type": "Feature",
    "geometry": {"type": "MultiPolygon", "coordinates": [[[[0,0],[1,0],[1,1],[0,0]]],
                                                        [[[2,2],[3,2],[3,3],[2,2]]]]},
    "properties": {"osm_way_id": 7, "context_delta": 3}})"),
                                     "o");
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0].polygons.size(), 2u);
  EXPECT_EQ(o[0].osm_way_ids, std::vector<std::int64_t>{7});
  EXPECT_EQ(o[0].context_delta, 3);
}

TEST(Overrides, BadFeaturesNameTheFeature) {
  const std::string ok = kDriveway + ",";
  EXPECT_EQ(
      error_of(
          ok +
          R"({"type": "Feature", "geometry": null, "properties": {"osm_way_id": 2, "colour": "red", "no_crossing": true}})"),
      "o.geojson: feature 1: unknown property \"colour\" (known: osm_way_id, context_delta, "
      "no_crossing, force_suitable, note)");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": null, "properties": {"osm_way_id": 2, "no_crossing": "yes"}})"),
      "o.geojson: feature 0: no_crossing must be true or false, got \"yes\"");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": null, "properties": {"osm_way_id": "2", "no_crossing": true}})"),
      "o.geojson: feature 0: osm_way_id must be a positive integer or an array of them, got \"2\"");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": null, "properties": {"osm_way_id": 2, "context_delta": 1.5}})"),
      "o.geojson: feature 0: context_delta must be an integer in [-1000, 1000], got 1.5");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0,0],[1,0],[1,1],[0,1]]]}, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: a polygon ring must be closed (first position = last position)");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0,0],[1,0],[0,0]]]}, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: a polygon ring must be an array of at least 4 positions");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0,0],[1,1],[2,2],[0,0]]]}, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: a polygon ring has no area");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": {"type": "Polygon", "coordinates": [[[0,0],[200,0],[1,1],[0,0]]]}, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: position [200, 0] is not a WGS84 longitude/latitude");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": {"type": "Point", "coordinates": [0,0]}, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: geometry type Point is not Polygon or MultiPolygon");
  EXPECT_EQ(
      error_of(R"({"type": "Feature", "geometry": null, "properties": {"no_crossing": true}})"),
      "o.geojson: feature 0: selects nothing: give a Polygon/MultiPolygon geometry or osm_way_id");
  EXPECT_EQ(
      error_of(
          R"({"type": "Feature", "geometry": null, "properties": {"osm_way_id": 2, "note": "x"}})"),
      "o.geojson: feature 0: has no effect: give context_delta, no_crossing or force_suitable");
  EXPECT_EQ(error_of(R"({"type": "Feat"})"),
            "o.geojson: feature 0: not a GeoJSON Feature (\"type\": \"Feature\")");
  EXPECT_THROW(rp::parse_overrides("{not json", "o"), rp::InputError);
  EXPECT_THROW(rp::parse_overrides(R"({"type": "Feature"})", "o"), rp::InputError);
}

TEST(Overrides, BadFileFailsTheBuildAndLeavesNoOutput) {
  rt::TempDir dir;
  rp::BuildOptions options;
  options.osm_path = kMap;
  options.output_path = dir.file("o.gpkg");
  options.overrides_path = dir.write("o.geojson", collection(R"({"type": "Feature"})"));
  EXPECT_THROW(rp::run_build(options), rp::InputError);
  EXPECT_FALSE(std::ifstream(options.output_path).good());
}

TEST(Overrides, TouchesPolygonEdgesAndHoles) {
  using P = roadcross::schema::PlanePoint;
  const std::vector<std::vector<P>> square = {{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}},
                                              {{4, 4}, {6, 4}, {6, 6}, {4, 6}, {4, 4}}};
  EXPECT_TRUE(rp::polyline_touches_polygon(std::vector<P>{{1, 1}, {2, 2}}, square));  // inside
  EXPECT_TRUE(
      rp::polyline_touches_polygon(std::vector<P>{{-5, 2}, {15, 2}}, square));  // passes through
  EXPECT_FALSE(
      rp::polyline_touches_polygon(std::vector<P>{{4.5, 5}, {5.5, 5}}, square));  // in the hole
  EXPECT_FALSE(
      rp::polyline_touches_polygon(std::vector<P>{{-5, -5}, {-1, 20}}, square));  // outside
}

}  // namespace
