// schema::judge_segment: the one suitability rule of every surface (assess, assess_segment,
// better_place and what is built on them). Each case states the rule it checks.
#include <gtest/gtest.h>

#include "roadcross/schema/verdict.hpp"

namespace rs = roadcross::schema;

namespace {

rs::VerdictTerms terms(std::optional<int> score, std::optional<int> context,
                       std::string_view reasons = "") {
  rs::VerdictTerms t;
  t.score = score;
  t.context_score = context;
  t.reasons = reasons;
  return t;
}

TEST(Verdict, ScorePlusContextAgainstTheThreshold) {
  const rs::VerdictThresholds at20{20.0, true};
  EXPECT_TRUE(rs::judge_segment(terms(11, 9), at20).suitable);    // 20 >= 20
  const rs::Verdict low = rs::judge_segment(terms(11, 8), at20);  // 19 < 20
  EXPECT_FALSE(low.suitable);
  EXPECT_TRUE(low.low_score);
  EXPECT_EQ(rs::forbidding_codes(low), std::vector<std::string_view>{"LOW_SCORE"});
  // No context counts as 0; no score is never enough.
  EXPECT_TRUE(rs::judge_segment(terms(15, std::nullopt), {15.0, true}).suitable);
  EXPECT_FALSE(rs::judge_segment(terms(std::nullopt, 30), at20).suitable);
  // Costs (NEAR_JUNCTION, SHARP_BEND, CREST_OR_DIP, BUSY_ROAD) are in the score, not vetoes.
  EXPECT_TRUE(
      rs::judge_segment(terms(12, 10, "NEAR_JUNCTION,SHARP_BEND,CREST_OR_DIP,BUSY_ROAD"), at20)
          .suitable);
}

TEST(Verdict, LimitedVisibilityForbidsUnlessInCostMode) {
  const rs::Verdict hidden =
      rs::judge_segment(terms(15, 10, "SHARP_BEND,LIMITED_VISIBILITY"), {20.0, true});
  EXPECT_FALSE(hidden.suitable);
  EXPECT_EQ(rs::forbidding_codes(hidden), std::vector<std::string_view>{"LIMITED_VISIBILITY"});
  EXPECT_TRUE(
      rs::judge_segment(terms(15, 10, "SHARP_BEND,LIMITED_VISIBILITY"), {20.0, false}).suitable);
  // A code that merely starts with the name is another code.
  EXPECT_TRUE(rs::judge_segment(terms(15, 10, "LIMITED_VISIBILITY_X"), {20.0, true}).suitable);
}

TEST(Verdict, OverridesClassAndTunnel) {
  rs::VerdictTerms forced = terms(1, 0, "LIMITED_VISIBILITY");
  forced.override_force_suitable = true;  // the operator knows of a mirror: low score, hidden
  EXPECT_TRUE(rs::judge_segment(forced, {20.0, true}).suitable);
  // ... but never over the class, a tunnel or a no_crossing override.
  rs::VerdictTerms motorway = forced;
  motorway.reasons = "NOT_CROSSABLE_CLASS";
  EXPECT_FALSE(rs::judge_segment(motorway, {20.0, true}).suitable);
  rs::VerdictTerms tunnel = forced;
  tunnel.tunnel = true;
  EXPECT_FALSE(rs::judge_segment(tunnel, {20.0, true}).suitable);
  rs::VerdictTerms everything = terms(15, 10, "NOT_CROSSABLE_CLASS,LIMITED_VISIBILITY");
  everything.tunnel = true;
  everything.override_no_crossing = true;
  EXPECT_EQ(rs::forbidding_codes(rs::judge_segment(everything, {30.0, true})),
            (std::vector<std::string_view>{"NOT_CROSSABLE_CLASS", "TUNNEL", "OVERRIDE",
                                           "LIMITED_VISIBILITY", "LOW_SCORE"}));
}

TEST(Verdict, HasReasonMatchesWholeCodes) {
  EXPECT_TRUE(rs::has_reason("A,B,C", "B"));
  EXPECT_TRUE(rs::has_reason("A", "A"));
  EXPECT_FALSE(rs::has_reason("AB,C", "A"));
  EXPECT_FALSE(rs::has_reason("", "A"));
  EXPECT_FALSE(rs::has_reason("A,", "B"));
}

}  // namespace
