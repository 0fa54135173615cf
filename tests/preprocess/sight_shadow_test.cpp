// The shadow an obstacle edge casts on one straight leg of the road (issue 27,
// sight_detail::leg_shadow and blocking_fractions), on geometry whose answer is worked out by hand.
#include <gtest/gtest.h>

#include "roadcross/preprocess/sight/shadow.hpp"

namespace sd = roadcross::preprocess::sight_detail;
using roadcross::schema::PlanePoint;

TEST(SightShadow, BlockingFractionsOfABandAlongARisingLine) {
  // The line rises from 0.6 m (sensor) to 1.1 m (vehicle): at fraction t it is 0.6 + 0.5 t high.
  // A building from the ground to 8 m covers the whole line.
  sd::BlockingFractions all = sd::blocking_fractions(0.0, 8.0, 0.6, 1.1);
  EXPECT_DOUBLE_EQ(all.from, 0.0);
  EXPECT_DOUBLE_EQ(all.to, 1.0);
  // Opaque from 0.8 m up (a passage under it): 0.6 + 0.5 t >= 0.8 from t = 0.4.
  sd::BlockingFractions above = sd::blocking_fractions(0.8, 8.0, 0.6, 1.1);
  EXPECT_NEAR(above.from, 0.4, 1e-12);
  EXPECT_DOUBLE_EQ(above.to, 1.0);
  // A 1 m wall: 0.6 + 0.5 t <= 1 up to t = 0.8.
  sd::BlockingFractions wall = sd::blocking_fractions(0.0, 1.0, 0.6, 1.1);
  EXPECT_DOUBLE_EQ(wall.from, 0.0);
  EXPECT_NEAR(wall.to, 0.8, 1e-12);
  // A 0.5 m kerb wall is below the whole line, a roof from 4 m above it.
  EXPECT_TRUE(sd::blocking_fractions(0.0, 0.5, 0.6, 1.1).empty());
  EXPECT_TRUE(sd::blocking_fractions(4.0, 20.0, 0.6, 1.1).empty());
}

TEST(SightShadow, AWallBetweenTheEyeAndTheRoadHidesTheStretchBehindIt) {
  // The eye at the origin, the road's leg along x = 10 from y = -5 (u = 0) to y = 5 (u = 1),
  // a wall from (5, 1) to (5, 3). Seen from the origin, (5, 1) lies on the line to (10, 2) and
  // (5, 3) on the line to (10, 6), beyond the leg's end: the lines to y in [2, 5] cross the wall,
  // u = (y + 5) / 10 in [0.7, 1].
  const PlanePoint eye{0, 0}, p0{10, -5}, p1{10, 5}, a{5, 1}, b{5, 3};
  const sd::BlockingFractions whole{0.0, 1.0};
  sd::LegShadow shadow = sd::leg_shadow(eye, p0, p1, a, b, whole);
  ASSERT_FALSE(shadow.empty());
  EXPECT_NEAR(shadow.from, 0.7, 1e-12);
  EXPECT_DOUBLE_EQ(shadow.to, 1.0);
  // The same with the leg walked the other way: u = (5 - y) / 10 in [0, 0.3].
  shadow = sd::leg_shadow(eye, p1, p0, a, b, whole);
  EXPECT_DOUBLE_EQ(shadow.from, 0.0);
  EXPECT_NEAR(shadow.to, 0.3, 1e-12);
  // The wall is half way along every line to the leg (x = 5 of 10): opaque only beyond 60 % of
  // a line it hides nothing, from 40 % on it hides the same stretch.
  EXPECT_TRUE(sd::leg_shadow(eye, p0, p1, a, b, {0.6, 1.0}).empty());
  shadow = sd::leg_shadow(eye, p0, p1, a, b, {0.4, 1.0});
  EXPECT_NEAR(shadow.from, 0.7, 1e-12);
  // A wall beyond the road (x = 12) hides nothing on it; one beside the wedge neither.
  EXPECT_TRUE(sd::leg_shadow(eye, p0, p1, {12, -5}, {12, 5}, whole).empty());
  EXPECT_TRUE(sd::leg_shadow(eye, p0, p1, {5, 3}, {5, 4}, whole).empty());
}

TEST(SightShadow, AWallAcrossAnObliqueLegEndsItsViewWhereTheLinesMeetIt) {
  // The leg from (10, 0) to (0, 10) (u = x distance / 10 from its start), a wall from (2, 2) to
  // (4, 4) on the diagonal y = x: the line to the leg's point (10 - 10u, 10u) lies on the
  // diagonal at u = 0.5 (the point (5, 5)); the wall spans the lines through (2, 2) and (4, 4),
  // both on that one line. So the wall, radial to the eye, hides exactly u = 0.5.
  const PlanePoint eye{0, 0}, p0{10, 0}, p1{0, 10};
  const sd::LegShadow radial = sd::leg_shadow(eye, p0, p1, {2, 2}, {4, 4}, {0.0, 1.0});
  ASSERT_FALSE(radial.empty());
  EXPECT_NEAR(radial.from, 0.5, 1e-12);
  EXPECT_NEAR(radial.to, 0.5, 1e-12);
  // A wall across the wedge from (3, 0) to (0, 3): every line from the eye to the leg crosses it
  // (at 30 % of its length), the whole leg is hidden.
  const sd::LegShadow across = sd::leg_shadow(eye, p0, p1, {3, 0}, {0, 3}, {0.0, 1.0});
  EXPECT_DOUBLE_EQ(across.from, 0.0);
  EXPECT_DOUBLE_EQ(across.to, 1.0);
  // Opaque only above 0.6 + 0.5 t >= 0.9 (t >= 0.6): the crossings at t = 0.3 do not count.
  EXPECT_TRUE(sd::leg_shadow(eye, p0, p1, {3, 0}, {0, 3}, {0.6, 1.0}).empty());
}

TEST(SightShadow, ALegInLineWithTheEyeIsHiddenBeyondTheWall) {
  // The leg runs straight away from the eye, from (10, 0) to (20, 0); a wall across it at
  // x = 15 hides the points farther than 15 m: u in [0.5, 1]. Walked towards the eye, [0, 0.5].
  const PlanePoint eye{0, 0};
  sd::LegShadow shadow = sd::leg_shadow(eye, {10, 0}, {20, 0}, {15, -1}, {15, 1}, {0.0, 1.0});
  EXPECT_NEAR(shadow.from, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(shadow.to, 1.0);
  shadow = sd::leg_shadow(eye, {20, 0}, {10, 0}, {15, -1}, {15, 1}, {0.0, 1.0});
  EXPECT_DOUBLE_EQ(shadow.from, 0.0);
  EXPECT_NEAR(shadow.to, 0.5, 1e-12);
  // A wall at x = 25, beyond the leg, hides none of it.
  EXPECT_TRUE(sd::leg_shadow(eye, {10, 0}, {20, 0}, {25, -1}, {25, 1}, {0.0, 1.0}).empty());
}

TEST(SightShadow, AnEdgeAcrossTheWholeWedgeCoversTheLegsEndsExactly) {
  // UTM coordinates from the bundled Monaco map, where the search's last position of a chunk is
  // the leg's end: every line from the eye to the leg crosses the edge (checked by hand: the
  // lines to p0, to p1 and to the midpoint cross it at 48 %, 44 % and 46 % of their length,
  // 71 %, 95 % and 83 % along the edge). The shadow must then be the whole leg, [0, 1] exactly:
  // a u computed from the clipped edge's end rounds just below 1, and the position at the leg's
  // end would be taken as seen.
  const PlanePoint eye{367248.7094, 4842464.4993};
  const PlanePoint p0{367246.1875, 4842462.8746}, p1{367248.8754, 4842458.7022};
  const PlanePoint a{367243.5166, 4842469.2197}, b{367249.0840, 4842461.5088};
  const sd::LegShadow shadow = sd::leg_shadow(eye, p0, p1, a, b, {0.0, 1.0});
  EXPECT_EQ(shadow.from, 0.0);
  EXPECT_EQ(shadow.to, 1.0);
}
