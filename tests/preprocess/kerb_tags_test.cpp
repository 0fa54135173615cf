// Kerb, island and pavement tags as OSM has them (roadcross/preprocess/context/kerb_tags.hpp).
// Expected values by hand: 1 in = 0.0254 m, 1 ft = 0.3048 m.
#include <gtest/gtest.h>

#include "roadcross/preprocess/context/crossings.hpp"
#include "roadcross/preprocess/context/kerb_tags.hpp"

namespace rp = roadcross::preprocess;

namespace {

TEST(KerbHeight, UnitsAsMappersWriteThem) {
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("0.12"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("0.12 m"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("0,12"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("12 cm"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("12cm"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m(" 3 cm "), 0.03);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("120 mm"), 0.12);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("4 in"), 4 * 0.0254);  // 0.1016 m
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("4\""), 4 * 0.0254);
  EXPECT_DOUBLE_EQ(*rp::parse_kerb_height_m("0"), 0.0);
}

TEST(KerbHeight, WhatIsNotUnderstoodIsUnknown) {
  EXPECT_FALSE(rp::parse_kerb_height_m(""));
  EXPECT_FALSE(rp::parse_kerb_height_m("high"));
  EXPECT_FALSE(rp::parse_kerb_height_m("-0.1"));
  EXPECT_FALSE(rp::parse_kerb_height_m("12"));     // 12 m: a mapper meant cm; not guessed
  EXPECT_FALSE(rp::parse_kerb_height_m("12 yd"));  // not a unit read
  EXPECT_FALSE(rp::parse_kerb_height_m("0.1.2"));
}

TEST(KerbHeight, UsualHeightsOfTheValues) {
  EXPECT_DOUBLE_EQ(*rp::usual_kerb_height_m("flush"), 0.0);
  EXPECT_DOUBLE_EQ(*rp::usual_kerb_height_m("no"), 0.0);
  EXPECT_DOUBLE_EQ(*rp::usual_kerb_height_m("lowered"), 0.03);
  EXPECT_DOUBLE_EQ(*rp::usual_kerb_height_m("rolled"), 0.03);
  EXPECT_DOUBLE_EQ(*rp::usual_kerb_height_m("raised"), 0.12);
  EXPECT_FALSE(rp::usual_kerb_height_m("yes"));
  EXPECT_FALSE(rp::usual_kerb_height_m("regular"));
}

TEST(KerbFacts, EveryTagForm) {
  // barrier=kerb alone: a kerb of unknown height.
  rp::KerbFacts f = rp::kerb_facts({{"barrier", "kerb"}});
  EXPECT_EQ(f.kerb, "yes");
  EXPECT_FALSE(f.kerb_height_m);
  EXPECT_FALSE(f.island);
  // kerb=* gives its usual height.
  f = rp::kerb_facts({{"barrier", "kerb"}, {"kerb", "raised"}});
  EXPECT_EQ(f.kerb, "raised");
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.12);
  // kerb:height alone: a kerb of that height.
  f = rp::kerb_facts({{"kerb:height", "4 in"}});
  EXPECT_EQ(f.kerb, "yes");
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.1016);
  // A crossing node's two sides: the higher counts (the robot climbs both).
  f = rp::kerb_facts({{"kerb:left", "lowered"}, {"kerb:right", "raised"}});
  EXPECT_EQ(f.kerb, "raised");
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.12);
  f = rp::kerb_facts({{"kerb:both", "flush"}});
  EXPECT_EQ(f.kerb, "flush");
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.0);
  // Islands.
  EXPECT_TRUE(*rp::kerb_facts({{"crossing:island", "yes"}}).island);
  EXPECT_TRUE(*rp::kerb_facts({{"traffic_calming", "island"}}).island);
  EXPECT_FALSE(*rp::kerb_facts({{"crossing:island", "no"}}).island);
  EXPECT_FALSE(rp::kerb_facts({{"traffic_calming", "bump"}}).island);
  // Nothing about kerbs at all.
  EXPECT_TRUE(rp::kerb_facts({{"highway", "crossing"}}).empty());
}

TEST(KerbFacts, ContradictoryTags) {
  // The measured height wins over the category: lowered but 12 cm high.
  rp::KerbFacts f = rp::kerb_facts({{"kerb", "lowered"}, {"kerb:height", "12 cm"}});
  EXPECT_EQ(f.kerb, "lowered");
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.12);
  // ... and raised but 2 cm: 0.02.
  f = rp::kerb_facts({{"kerb", "raised"}, {"kerb:height", "2 cm"}});
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.02);
  // A height not understood falls back to the value's usual one.
  f = rp::kerb_facts({{"kerb", "raised"}, {"kerb:height", "high"}});
  EXPECT_DOUBLE_EQ(*f.kerb_height_m, 0.12);
  // crossing:island=no and traffic_calming=island: an island is there.
  EXPECT_TRUE(*rp::kerb_facts({{"crossing:island", "no"}, {"traffic_calming", "island"}}).island);
}

TEST(KerbFacts, MergingKeepsTheHighestKnownKerbAndAnyIsland) {
  rp::KerbFacts a = rp::kerb_facts({{"kerb", "lowered"}});
  rp::merge_kerb_facts(a, rp::kerb_facts({{"barrier", "kerb"}}));  // unknown height: no change
  EXPECT_EQ(a.kerb, "lowered");
  EXPECT_DOUBLE_EQ(*a.kerb_height_m, 0.03);
  rp::merge_kerb_facts(a, rp::kerb_facts({{"kerb", "raised"}}));
  EXPECT_EQ(a.kerb, "raised");
  EXPECT_DOUBLE_EQ(*a.kerb_height_m, 0.12);
  rp::merge_kerb_facts(a, rp::kerb_facts({{"kerb", "flush"}}));  // lower: no change
  EXPECT_EQ(a.kerb, "raised");
  EXPECT_FALSE(a.island);
  rp::merge_kerb_facts(a, rp::kerb_facts({{"crossing:island", "no"}}));
  EXPECT_FALSE(*a.island);
  rp::merge_kerb_facts(a, rp::kerb_facts({{"crossing:island", "yes"}}));
  EXPECT_TRUE(*a.island);
  rp::merge_kerb_facts(a, rp::kerb_facts({{"crossing:island", "no"}}));  // a yes stays
  EXPECT_TRUE(*a.island);
}

void expect_sides(const rp::Tags& tags, std::optional<bool> left, std::optional<bool> right) {
  const rp::SidewalkSides sides = rp::sidewalk_sides(tags);
  EXPECT_EQ(sides.left, left) << tags.front().first << "=" << tags.front().second;
  EXPECT_EQ(sides.right, right) << tags.front().first << "=" << tags.front().second;
}

TEST(SidewalkSides, EveryTagForm) {
  expect_sides({{"sidewalk", "both"}}, true, true);
  expect_sides({{"sidewalk", "left"}}, true, false);
  expect_sides({{"sidewalk", "right"}}, false, true);
  expect_sides({{"sidewalk", "no"}}, false, false);
  expect_sides({{"sidewalk", "none"}}, false, false);
  expect_sides({{"sidewalk", "separate"}}, true, true);
  expect_sides({{"sidewalk", "yes"}}, std::nullopt, std::nullopt);  // names no side
  expect_sides({{"sidewalk:both", "no"}}, false, false);
  expect_sides({{"sidewalk:both", "separate"}}, true, true);
  expect_sides({{"sidewalk:left", "yes"}}, true, std::nullopt);
  expect_sides({{"sidewalk:right", "separate"}}, std::nullopt, true);
  expect_sides({{"highway", "residential"}}, std::nullopt, std::nullopt);
}

TEST(SidewalkSides, TheMoreSpecificKeyWins) {
  expect_sides({{"sidewalk", "both"}, {"sidewalk:left", "no"}}, false, true);
  expect_sides({{"sidewalk", "no"}, {"sidewalk:right", "separate"}}, false, true);
  expect_sides({{"sidewalk:both", "yes"}, {"sidewalk:right", "no"}}, true, false);
  expect_sides({{"sidewalk", "left"}, {"sidewalk:both", "no"}}, false, false);
  // A value not understood on the side key leaves the general one.
  expect_sides({{"sidewalk", "both"}, {"sidewalk:left", "maybe"}}, true, true);
}

TEST(TactilePaving, MarksADesignatedCrossing) {
  const auto kind = rp::node_crossing_kind({{"tactile_paving", "yes"}});
  ASSERT_TRUE(kind);
  EXPECT_TRUE(kind->designated);
  EXPECT_EQ(kind->type, "unspecified");
  EXPECT_FALSE(rp::node_crossing_kind({{"tactile_paving", "no"}}));
  EXPECT_FALSE(rp::node_crossing_kind({{"barrier", "kerb"}, {"kerb", "lowered"}}));
}

}  // namespace
