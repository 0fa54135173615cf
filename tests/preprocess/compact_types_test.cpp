// ReasonSet and Maybe<T>: the compact per-segment storage behaves like the vector of strings and
// std::optional it replaced; the metadata keys the build and the runtime share.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "roadcross/preprocess/common/maybe.hpp"
#include "roadcross/preprocess/common/reasons.hpp"
#include "roadcross/preprocess/parameters.hpp"
#include "roadcross/schema/schema.hpp"

namespace rp = roadcross::preprocess;

TEST(ReasonSet, KeepsCanonicalOrderAndEachCodeOnce) {
  rp::ReasonSet r;
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.joined(','), "");
  r.add("NO_ELEVATION");
  r.add("SHARP_BEND");
  r.add("NOT_CROSSABLE_CLASS");
  r.add("SHARP_BEND");
  // schema::kReasons order: what forbids crossing first.
  EXPECT_EQ(r.list(),
            (std::vector<std::string>{"NOT_CROSSABLE_CLASS", "SHARP_BEND", "NO_ELEVATION"}));
  EXPECT_EQ(r.joined(','), "NOT_CROSSABLE_CLASS,SHARP_BEND,NO_ELEVATION");
  EXPECT_TRUE(r.contains("SHARP_BEND"));
  EXPECT_FALSE(r.contains("TUNNEL"));
  EXPECT_THROW(r.add("SHARP_BENDS"), std::logic_error);
  rp::ReasonSet same;
  same.add("NOT_CROSSABLE_CLASS");
  same.add("NO_ELEVATION");
  EXPECT_NE(same, r);
  same.add("SHARP_BEND");
  EXPECT_EQ(same, r);
}

TEST(Maybe, BehavesLikeOptional) {
  rp::MaybeFloat absent;
  EXPECT_FALSE(absent.has_value());
  EXPECT_TRUE(absent == std::nullopt);
  EXPECT_EQ(absent.value_or(7.0f), 7.0f);
  EXPECT_EQ(absent.optional(), std::nullopt);
  rp::MaybeFloat width = 6.096;  // a double stored at float precision
  ASSERT_TRUE(width);
  EXPECT_NEAR(*width, 6.096, 1e-6);
  EXPECT_EQ(*width, 6.096f);
  width = std::nullopt;
  EXPECT_FALSE(width);
  rp::MaybeFloat from_nan = std::nan("");
  EXPECT_FALSE(from_nan);
  rp::MaybeInt rank = std::optional<int>(0);  // zero is a value, not absence
  ASSERT_TRUE(rank);
  EXPECT_EQ(*rank, 0);
  EXPECT_EQ(rank.optional(), std::optional<int>(0));
  rp::MaybeInt none = std::optional<int>();
  EXPECT_FALSE(none);
  EXPECT_EQ(none.value_or(-1), -1);
}

TEST(Maybe, SmallIntWidensToIntKeepingAbsence) {
  rp::MaybeSmallInt rank;
  EXPECT_FALSE(rank);
  EXPECT_FALSE(rp::MaybeInt(rank));  // absent stays absent, not -128
  rank = 14;
  EXPECT_EQ(sizeof(rank), 1u);
  const rp::MaybeInt wide = rank;
  ASSERT_TRUE(wide);
  EXPECT_EQ(*wide, 14);
  rank = 0;  // zero is a value
  EXPECT_EQ(rp::MaybeInt(rank).optional(), std::optional<int>(0));
  rank = -127;  // the smallest value (-128 is the absence sentinel)
  EXPECT_EQ(*rp::MaybeInt(rank), -127);
  EXPECT_EQ(rank.value_or(3) + 1, -126);  // arithmetic in int, not a wrapped char
}

// The runtime reads the map's default thresholds back by the keys schema::meta names: the build
// must record exactly those keys, with the defaults of docs/cost-model.md (10 m, 20, 1).
TEST(MetadataContract, TheBuildRecordsTheThresholdsTheRuntimeReads) {
  std::map<std::string, std::string> recorded;
  for (const auto& [key, value] : rp::Parameters{}.as_metadata()) recorded[key] = value;
  namespace meta = roadcross::schema::meta;
  EXPECT_EQ(recorded[std::string(meta::kValidDistanceParam)], "10");
  EXPECT_EQ(recorded[std::string(meta::kThresholdParam)], "20");
  EXPECT_EQ(recorded[std::string(meta::kLimitedVisibilityUnsuitableParam)], "1");
}
