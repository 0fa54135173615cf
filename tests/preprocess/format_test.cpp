// Numbers for people in the build's progress line: never "9.562e+04 segments/s".
#include <gtest/gtest.h>

#include <limits>

#include "roadcross/preprocess/common/format.hpp"

namespace rp = roadcross::preprocess;

TEST(FormatCount, GroupsThousands) {
  EXPECT_EQ(rp::format_count(0), "0");
  EXPECT_EQ(rp::format_count(999), "999");
  EXPECT_EQ(rp::format_count(1000), "1,000");
  EXPECT_EQ(rp::format_count(95620), "95,620");
  EXPECT_EQ(rp::format_count(1234567.4), "1,234,567");
  EXPECT_EQ(rp::format_count(-4812), "-4,812");
  EXPECT_EQ(rp::format_count(-0.2), "0");  // rounds to zero: no "-0"
  EXPECT_EQ(rp::format_count(std::numeric_limits<double>::infinity()), "-");
}

TEST(FormatQuantity, NeverExponentForm) {
  EXPECT_EQ(rp::format_quantity(95620.0), "95,620");  // was "9.562e+04"
  EXPECT_EQ(rp::format_quantity(1.5e9), "1,500,000,000");
  EXPECT_EQ(rp::format_quantity(100.0), "100");
  EXPECT_EQ(rp::format_quantity(42.46), "42.5");  // three significant digits below 100
  EXPECT_EQ(rp::format_quantity(0.1234), "0.123");
  EXPECT_EQ(rp::format_quantity(0.0), "0");
}
