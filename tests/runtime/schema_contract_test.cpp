// The DB contract in schema/: the segments columns by name and the reason codes table.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/schema/reasons.hpp"
#include "roadcross/schema/schema.hpp"

namespace schema = roadcross::schema;
using C = schema::SegmentColumn;

// Every enumerator names the column of its position: the list is written out by hand, so that a
// column inserted into the table but not into the enum (or in another place) fails here.
TEST(SchemaContract, EachSegmentColumnEnumeratorNamesItsColumn) {
  const std::vector<std::pair<C, std::string>> expected = {
      {C::osm_way_id, "osm_way_id"},
      {C::highway, "highway"},
      {C::name, "name"},
      {C::length_m, "length_m"},
      {C::from_node_id, "from_node_id"},
      {C::to_node_id, "to_node_id"},
      {C::oneway, "oneway"},
      {C::tunnel, "tunnel"},
      {C::bridge, "bridge"},
      {C::class_cost, "class_cost"},
      {C::junction_distance_m, "junction_distance_m"},
      {C::radius_m, "radius_m"},
      {C::curvature_level, "curvature_level"},
      {C::curvature_cost, "curvature_cost"},
      {C::elevation_m, "elevation_m"},
      {C::slope_deg, "slope_deg"},
      {C::grade_percent, "grade_percent"},
      {C::tpi_small_m, "tpi_small_m"},
      {C::tpi_large_m, "tpi_large_m"},
      {C::landform, "landform"},
      {C::elevation_cost, "elevation_cost"},
      {C::maxspeed_kmh, "maxspeed_kmh"},
      {C::lanes, "lanes"},
      {C::width_m, "width_m"},
      {C::context_score, "context_score"},
      {C::crossing_distance_m, "crossing_distance_m"},
      {C::context_defaulted, "context_defaulted"},
      {C::override_note, "override_note"},
      {C::override_no_crossing, "override_no_crossing"},
      {C::override_force_suitable, "override_force_suitable"},
      {C::rank, "rank"},
      {C::score, "score"},
      {C::reasons, "reasons"},
      {C::sight_forward_m, "sight_forward_m"},
      {C::sight_backward_m, "sight_backward_m"},
      {C::sight_min_m, "sight_min_m"},
      {C::required_sight_m, "required_sight_m"},
      {C::kerb, "kerb"},
      {C::kerb_height_m, "kerb_height_m"},
      {C::crossing_island, "crossing_island"},
      {C::sidewalk_left, "sidewalk_left"},
      {C::sidewalk_right, "sidewalk_right"},
      {C::suitable, "suitable"},
  };
  ASSERT_EQ(schema::segment_columns().size(), expected.size());
  ASSERT_EQ(schema::kSegmentColumnCount, expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(static_cast<std::size_t>(expected[i].first), i) << expected[i].second;
    EXPECT_EQ(schema::column_spec(expected[i].first).name, expected[i].second);
  }
}

TEST(SchemaContract, SelectionGivesPositionsAndNullsForNewerColumns) {
  const schema::SegmentSelection selection({C::score, C::sight_min_m, C::name}, 2);
  EXPECT_EQ(selection[C::score], 2);
  EXPECT_EQ(selection[C::sight_min_m], 3);
  EXPECT_EQ(selection[C::name], 4);
  EXPECT_THROW(static_cast<void>(selection[C::rank]), std::logic_error);
  EXPECT_EQ(selection.sql("s", 2), "s.score, s.sight_min_m, s.name");
  // The sight columns came with schema version 2: a version 1 map reads NULL in their place.
  EXPECT_EQ(selection.sql("", 1), "score, NULL, name");
  // The stored verdict came with schema version 4.
  const schema::SegmentSelection verdict({C::suitable});
  EXPECT_EQ(verdict.sql("", 3), "NULL");
  EXPECT_EQ(verdict.sql("", 4), "suitable");
}

TEST(SchemaContract, ReasonCodesAreUniqueStoredOnesFirst) {
  std::set<std::string_view> codes;
  for (std::size_t i = 0; i < schema::kReasons.size(); ++i) {
    const schema::ReasonSpec& reason = schema::kReasons[i];
    EXPECT_TRUE(codes.insert(reason.code).second) << reason.code;
    EXPECT_FALSE(reason.sentence.empty()) << reason.code;
    EXPECT_EQ(reason.stored_by_build, i < schema::kStoredReasonCount) << reason.code;
    EXPECT_EQ(schema::reason_index(reason.code), i);
    EXPECT_EQ(schema::find_reason(reason.code), &reason);
  }
  EXPECT_EQ(schema::find_reason("BRIDGE"), nullptr);  // defined once, never written: gone
  EXPECT_EQ(schema::reason_index("SHARP_BENDS"), schema::kReasons.size());
}

TEST(SchemaContract, WhatForbidsByItself) {
  std::vector<std::string_view> forbidding;
  for (const schema::ReasonSpec& reason : schema::kReasons) {
    if (reason.makes_unsuitable) forbidding.push_back(reason.code);
  }
  EXPECT_EQ(forbidding,
            (std::vector<std::string_view>{"NOT_CROSSABLE_CLASS", "TUNNEL", "LIMITED_VISIBILITY",
                                           "TOO_FAR_FROM_ROAD", "LOW_SCORE", "KERB_TOO_HIGH",
                                           "NO_PAVEMENT_FAR_SIDE", "POSITION_UNCERTAIN",
                                           "AMBIGUOUS_ROAD"}));
}
