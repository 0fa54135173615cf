// Tag parsing on the value forms found in real OSM data (the bundled maps and taginfo's most
// common values for maxspeed, lanes and width).
#include <gtest/gtest.h>

#include "roadcross/preprocess/context/osm_tags.hpp"

namespace rp = roadcross::preprocess;

namespace {

double kmh(std::string_view value, std::string_view country = "CZ") {
  const auto v = rp::parse_maxspeed_kmh(value, country);
  return v ? *v : -1.0;
}

TEST(TagParsing, MaxspeedNumbersAndUnits) {
  EXPECT_EQ(kmh("50"), 50);
  EXPECT_EQ(kmh("50 km/h"), 50);
  EXPECT_EQ(kmh("50 kmh"), 50);
  EXPECT_NEAR(kmh("30 mph"), 48.28032, 1e-9);
  EXPECT_NEAR(kmh("10 knots"), 18.52, 1e-9);
  EXPECT_EQ(kmh(" 70 "), 70);
  EXPECT_EQ(kmh("50;30"), 50);  // several values: the higher
  EXPECT_EQ(kmh("30;50;70"), 70);
}

TEST(TagParsing, MaxspeedZonesFromTheNationalTable) {
  EXPECT_EQ(kmh("CZ:urban"), 50);
  EXPECT_EQ(kmh("CZ:rural"), 90);
  EXPECT_EQ(kmh("CZ:motorway"), 130);
  EXPECT_EQ(kmh("CZ:living_street"), 20);
  EXPECT_EQ(kmh("CZ:trunk"), 110);
  EXPECT_EQ(kmh("DE:urban"), 50);
  EXPECT_EQ(kmh("DE:rural"), 100);
  EXPECT_EQ(kmh("DE:zone30"), 30);
  EXPECT_EQ(kmh("DE:zone:30"), 30);
  EXPECT_EQ(kmh("DE:30"), 30);  // zone:maxspeed=DE:30
  EXPECT_EQ(kmh("DE:motorway"), rp::kNoLimitKmh);
  EXPECT_EQ(kmh("AT:rural"), 100);
  EXPECT_EQ(kmh("AT:motorway"), 130);
  EXPECT_EQ(kmh("SK:rural"), 90);
  EXPECT_EQ(kmh("PL:motorway"), 140);
  EXPECT_EQ(kmh("PL:expressway"), 120);
  EXPECT_EQ(kmh("FR:rural"), 80);
  EXPECT_EQ(kmh("MC:urban"), 50);
  EXPECT_EQ(kmh("cz:urban"), 50);     // case of the prefix does not matter
  EXPECT_EQ(kmh("RO:urban"), 50);     // unknown country: the default rows
  EXPECT_EQ(kmh("SK:trunk"), 90);     // no trunk row: the country's rural limit
  EXPECT_EQ(kmh("urban", "DE"), 50);  // Monaco's extract has bare maxspeed=urban / rural
  EXPECT_EQ(kmh("rural", "DE"), 100);
  EXPECT_EQ(kmh("CZ:nonsense"), -1);
}

TEST(TagParsing, MaxspeedWords) {
  EXPECT_EQ(kmh("walk"), 7);
  EXPECT_EQ(kmh("none"), rp::kNoLimitKmh);
  EXPECT_EQ(kmh("signals"), -1);  // variable: no number in the data, the caller defaults
  EXPECT_EQ(kmh("variable"), -1);
  EXPECT_EQ(kmh("fast"), -1);
  EXPECT_EQ(kmh(""), -1);
  EXPECT_EQ(kmh("50 km"), -1);
  EXPECT_EQ(kmh("50;fast"), -1);
  EXPECT_EQ(kmh("0"), -1);
}

TEST(TagParsing, EveryCountryOfTheIssueHasItsRowsAndASource) {
  for (const char* country : {"CZ", "SK", "DE", "AT", "PL", "FR", "MC", "default"}) {
    EXPECT_TRUE(rp::has_implicit_speeds(country)) << country;
    EXPECT_TRUE(rp::implicit_speed_kmh(country, "urban")) << country;
    EXPECT_TRUE(rp::implicit_speed_kmh(country, "rural")) << country;
    EXPECT_TRUE(rp::implicit_speed_kmh(country, "motorway")) << country;
    EXPECT_TRUE(rp::implicit_speed_kmh(country, "living_street")) << country;
  }
  for (const rp::ImplicitSpeed& row : rp::implicit_speed_table()) {
    EXPECT_FALSE(row.source.empty()) << row.country << ":" << row.zone;
    EXPECT_GT(row.kmh, 0) << row.country << ":" << row.zone;
  }
  EXPECT_FALSE(rp::has_implicit_speeds("XX"));
}

TEST(TagParsing, Lanes) {
  EXPECT_EQ(rp::parse_lanes("2"), 2);
  EXPECT_EQ(rp::parse_lanes("2;3"), 3);
  EXPECT_EQ(rp::parse_lanes(" 1 "), 1);
  EXPECT_EQ(rp::parse_lanes("left"), std::nullopt);  // seen in Prague
  EXPECT_EQ(rp::parse_lanes("1.5"), std::nullopt);
  EXPECT_EQ(rp::parse_lanes("0"), std::nullopt);
  EXPECT_EQ(rp::parse_lanes(""), std::nullopt);
}

TEST(TagParsing, LanesFromDirectionsAndDefaults) {
  const rp::ContextDefaults d;
  const auto lanes = [&](rp::Tags tags, std::string_view highway, bool oneway) {
    return rp::way_context(tags, highway, oneway, d).lanes;
  };
  EXPECT_EQ(lanes({{"lanes:forward", "2"}, {"lanes:backward", "1"}}, "secondary", false), 3);
  EXPECT_EQ(lanes({{"lanes:forward", "2"}}, "secondary", true), 2);
  EXPECT_EQ(lanes({{"lanes:forward", "2"}}, "secondary", false), 2);  // other side unknown: default
  EXPECT_EQ(lanes({}, "residential", false), 2);
  EXPECT_EQ(lanes({}, "residential", true), 1);
  EXPECT_EQ(lanes({}, "motorway", true), 2);
  EXPECT_EQ(lanes({}, "trunk", false), 4);
  EXPECT_EQ(lanes({}, "service", false), 1);
  EXPECT_EQ(
      lanes({{"lanes", "left"}, {"lanes:forward", "1"}, {"lanes:backward", "1"}}, "primary", false),
      2);
}

TEST(TagParsing, Width) {
  EXPECT_EQ(rp::parse_width_m("6"), 6.0);
  EXPECT_EQ(rp::parse_width_m("6 m"), 6.0);
  EXPECT_EQ(rp::parse_width_m("6.5m"), 6.5);
  EXPECT_EQ(rp::parse_width_m("6,5"), 6.5);
  EXPECT_NEAR(*rp::parse_width_m("20'"), 6.096, 1e-12);
  EXPECT_NEAR(*rp::parse_width_m("20 ft"), 6.096, 1e-12);
  EXPECT_NEAR(*rp::parse_width_m("20'6\""), 6.2484, 1e-12);
  EXPECT_NEAR(*rp::parse_width_m("6 ft 6 in"), 1.9812, 1e-12);
  EXPECT_EQ(rp::parse_width_m("2.5"), 2.5);  // Bayreuth
  EXPECT_EQ(rp::parse_width_m("0.5"), 0.5);  // Monaco (a kerb, but a valid width)
  EXPECT_EQ(rp::parse_width_m("wide"), std::nullopt);
  EXPECT_EQ(rp::parse_width_m("0"), std::nullopt);
  EXPECT_EQ(rp::parse_width_m("6 yards"), std::nullopt);
  EXPECT_EQ(rp::parse_width_m("500"), std::nullopt);
}

TEST(TagParsing, WayContextOrderAndDefaults) {
  rp::ContextDefaults d;
  d.country = "DE";
  // maxspeed beats source:maxspeed; the higher of maxspeed and maxspeed:backward.
  auto c = rp::way_context(
      {{"maxspeed", "50"}, {"maxspeed:backward", "30"}, {"source:maxspeed", "DE:rural"}},
      "residential", false, d);
  EXPECT_EQ(c.maxspeed_kmh, 50);
  EXPECT_EQ(c.defaulted, (std::vector<std::string>{"lanes", "width"}));
  // Not understood: the default, and recorded both as defaulted and as not understood.
  c = rp::way_context({{"maxspeed", "signals"}, {"width", "wide"}}, "tertiary", false, d);
  EXPECT_EQ(c.maxspeed_kmh, 50);  // DE:urban
  EXPECT_EQ(c.defaulted, (std::vector<std::string>{"maxspeed", "lanes", "width"}));
  EXPECT_EQ(c.unparsed, (std::vector<std::string>{"maxspeed", "width"}));
  // width:carriageway first, then width, then est_width; default from lanes and class.
  EXPECT_EQ(rp::way_context({{"width", "8"}, {"est_width", "5"}}, "residential", false, d).width_m,
            8);
  EXPECT_EQ(rp::way_context({{"lanes", "3"}}, "primary", false, d).width_m, 3 * 3.5);
  EXPECT_EQ(rp::way_context({{"lanes", "3"}}, "residential", false, d).width_m, 3 * 3.0);
  // Untagged classes: motorway in DE has no limit, living streets are walking pace.
  EXPECT_EQ(rp::way_context({}, "motorway", true, d).maxspeed_kmh, rp::kNoLimitKmh);
  EXPECT_EQ(rp::way_context({}, "living_street", false, d).maxspeed_kmh, 7);
  d.assume_urban = false;
  EXPECT_EQ(rp::way_context({}, "residential", false, d).maxspeed_kmh, 100);
}

}  // namespace
