// parse_utm_zone: the written forms a user gives a set of maps with a UTM position.
#include <gtest/gtest.h>

#include "roadcross/map_set.hpp"

using roadcross::parse_utm_zone;
using roadcross::geo::UtmZone;

TEST(ParseUtmZone, NumberAndHemisphere) {
  EXPECT_EQ(parse_utm_zone("33N"), (UtmZone{33, true}));
  EXPECT_EQ(parse_utm_zone("34S"), (UtmZone{34, false}));
  EXPECT_EQ(parse_utm_zone("7n"), (UtmZone{7, true}));
  EXPECT_EQ(parse_utm_zone("60s"), (UtmZone{60, false}));
  EXPECT_EQ(parse_utm_zone("33"), (UtmZone{33, true}));  // north unless S
}

TEST(ParseUtmZone, AnythingElseIsNoZone) {
  for (const char* text : {"", "0N", "61N", "99X", "N", "33NS", "333", "-3N", " 33N", "33 N"}) {
    EXPECT_FALSE(parse_utm_zone(text).has_value()) << text;
  }
}
