// roadcross::viz pieces with answers known by hand: colour scales, bbox parsing and checking.
#include <gtest/gtest.h>

#include <stdexcept>

#include "roadcross/viz/colors.hpp"
#include "roadcross/viz/layers.hpp"

namespace rv = roadcross::viz;

TEST(Colors, ParseColorByKnowsTheTerms) {
  EXPECT_EQ(rv::parse_color_by("suitable"), rv::ColorBy::suitable);
  EXPECT_EQ(rv::parse_color_by("rank"), rv::ColorBy::rank);
  EXPECT_EQ(rv::parse_color_by("landform"), rv::ColorBy::landform);
  EXPECT_EQ(rv::parse_color_by("context"), rv::ColorBy::context);
  EXPECT_FALSE(rv::parse_color_by("speed"));
  EXPECT_FALSE(rv::parse_color_by("Suitable"));
}

TEST(Colors, HexRoundTripsAndViridisEndsAtItsPublishedStops) {
  EXPECT_EQ(rv::rgb_from_hex("#0072b2").hex(), "#0072b2");
  EXPECT_EQ(rv::viridis(0.0).hex(), "#440154");
  EXPECT_EQ(rv::viridis(0.5).hex(), "#21918c");
  EXPECT_EQ(rv::viridis(1.0).hex(), "#fde725");
  EXPECT_EQ(rv::viridis(7.0).hex(), "#fde725");  // clamped
}

TEST(Colors, SuitableAndRankFollowTheAssessment) {
  roadcross::Assessment a;
  a.suitable = true;
  a.rank = 0;
  const rv::ColorScale suitable(rv::ColorBy::suitable, 20.0, 0, 10);
  EXPECT_EQ(suitable.color_of(a).hex(), "#0072b2");
  a.suitable = false;
  EXPECT_EQ(suitable.color_of(a).hex(), "#d55e00");
  const rv::ColorScale rank(rv::ColorBy::rank, 20.0, 0, 10);
  EXPECT_EQ(rank.color_of(a).hex(), "#fde725");  // rank 0 is the best: yellow
  a.rank = 14;
  EXPECT_EQ(rank.color_of(a).hex(), "#440154");
  a.rank.reset();
  EXPECT_EQ(rank.color_of(a).hex(), rv::kMissingColor.hex());
  EXPECT_EQ(rank.legend({}).size(), 8u);  // ranks 0, 2, ..., 14
}

TEST(Colors, ContextSpreadsOverTheMapsRangeAndLandformListsOnlyPresentClasses) {
  roadcross::Assessment a;
  const rv::ColorScale context(rv::ColorBy::context, 20.0, -4, 12);
  a.context_score = -4;
  EXPECT_EQ(context.color_of(a).hex(), "#440154");
  a.context_score = 12;
  EXPECT_EQ(context.color_of(a).hex(), "#fde725");
  const rv::ColorScale landform(rv::ColorBy::landform, 20.0, 0, 1);
  const auto legend = landform.legend({"plains", "tunnel"});
  ASSERT_EQ(legend.size(), 2u);
  EXPECT_EQ(legend[0].label, "plains");
  EXPECT_EQ(legend[1].label, "tunnel");
  EXPECT_EQ(landform.legend({}).front().label, "no elevation data");
}

TEST(Colors, ReasonColoursTheDecidingCodeAndListsOnlyPresentOnesInTheContractsOrder) {
  EXPECT_EQ(rv::parse_color_by("reason"), rv::ColorBy::reason);
  EXPECT_STREQ(rv::to_string(rv::ColorBy::reason), "reason");
  roadcross::Assessment a;
  const rv::ColorScale reason(rv::ColorBy::reason, 20.0, 0, 1);
  EXPECT_EQ(reason.color_of(a, "").hex(), "#0072b2");  // suitable: the verdict's blue
  EXPECT_EQ(reason.color_of(a, "LIMITED_VISIBILITY").hex(), "#d55e00");
  EXPECT_EQ(reason.color_of(a, "NOT_CROSSABLE_CLASS").hex(), "#000000");
  EXPECT_EQ(reason.color_of(a, "NEAR_JUNCTION").hex(), rv::kMissingColor.hex());  // never decides
  // Given out of order, listed as schema::kReasons orders them, after "suitable".
  const auto legend = reason.legend({"LOW_SCORE", "", "TUNNEL"});
  ASSERT_EQ(legend.size(), 3u);
  EXPECT_EQ(legend[0].label, "suitable");
  EXPECT_EQ(legend[1].label, "TUNNEL");
  EXPECT_EQ(legend[2].label, "LOW_SCORE");
}

TEST(Bbox, ParsesFourNumbersAndRejectsTheRest) {
  const rv::LonLatBox b = rv::parse_bbox("14.41,50.07,14.43,50.08");
  EXPECT_DOUBLE_EQ(b.min_lon_deg, 14.41);
  EXPECT_DOUBLE_EQ(b.max_lat_deg, 50.08);
  EXPECT_THROW(rv::parse_bbox("14.41,50.07,14.43"), std::invalid_argument);
  EXPECT_THROW(rv::parse_bbox("14.41,50.07,14.43,50.08,1"), std::invalid_argument);
  EXPECT_THROW(rv::parse_bbox("14.43,50.07,14.41,50.08"), std::invalid_argument);  // min > max
  EXPECT_THROW(rv::parse_bbox("14.41,89,14.43,89.5"), std::invalid_argument);      // not UTM
  EXPECT_THROW(rv::parse_bbox("a,b,c,d"), std::invalid_argument);
}

TEST(Bbox, MustOverlapTheMap) {
  roadcross::MapInfo info;
  info.zone = {33, true};
  info.epsg = 32633;
  // About Prague's Nové Město in UTM 33N.
  info.min_easting_m = 457300;
  info.max_easting_m = 460000;
  info.min_northing_m = 5546200;
  info.max_northing_m = 5548100;
  const rv::UtmBox inside = rv::bbox_in_map(rv::parse_bbox("14.418,50.074,14.424,50.078"), info);
  EXPECT_LT(inside.min_e_m, inside.max_e_m);
  EXPECT_NEAR(inside.width_m(), 0.006 * 111320 * 0.6418, 15.0);  // 0.006 deg of longitude at 50 N
  try {
    rv::bbox_in_map(rv::parse_bbox("16.0,49.0,16.1,49.1"), info);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lies outside the map (it covers 14.4"), std::string::npos)
        << e.what();
  }
}
