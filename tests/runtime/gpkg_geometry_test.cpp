// GeoPackage geometry blobs: what roadcross writes reads back, and malformed blobs are rejected
// without reading past their end (run under ASan in the asan preset).
#include <gtest/gtest.h>

#include <cstring>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace schema = roadcross::schema;

namespace {

TEST(GpkgGeometry, LinestringRoundTripAndLayout) {
  const std::vector<schema::PlanePoint> points = {
      {458000.5, 5547000.25}, {458010.0, 5547001.0}, {458009.0, 5546990.0}};
  const std::vector<std::uint8_t> blob = schema::encode_linestring(points, 32633);
  // Header (8) + XY envelope (32) + WKB byte order (1) + type (4) + count (4) + 3 points (48).
  ASSERT_EQ(blob.size(), 8u + 32u + 1u + 4u + 4u + 48u);
  EXPECT_EQ(blob[0], 'G');
  EXPECT_EQ(blob[1], 'P');
  EXPECT_EQ(blob[2], 0);     // version 1
  EXPECT_EQ(blob[3], 0x03);  // little-endian, envelope code 1 (minx, maxx, miny, maxy)
  EXPECT_EQ(blob[4] | (blob[5] << 8) | (blob[6] << 16) | (blob[7] << 24), 32633);
  double min_x = 0, max_y = 0;
  std::memcpy(&min_x, blob.data() + 8, 8);
  std::memcpy(&max_y, blob.data() + 8 + 24, 8);
  EXPECT_EQ(min_x, 458000.5);
  EXPECT_EQ(max_y, 5547001.0);
  std::vector<schema::PlanePoint> decoded;
  ASSERT_TRUE(schema::decode_linestring(blob, decoded));
  ASSERT_EQ(decoded.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(decoded[i].x, points[i].x);
    EXPECT_EQ(decoded[i].y, points[i].y);
  }
}

TEST(GpkgGeometry, LinestringIntoABufferReplacesItsContents) {
  // The writer encodes every row's line into one buffer: a longer line before, then a shorter
  // one, leaves exactly the shorter one's bytes (the same as encoding it afresh), in the
  // buffer's own storage once it is large enough.
  const std::vector<schema::PlanePoint> longer = {{1.0, 2.0}, {3.0, 4.0}, {5.0, 7.0}, {6.0, 1.0}};
  const std::vector<schema::PlanePoint> shorter = {{458000.5, 5547000.25}, {458010.0, 5547001.0}};
  std::vector<std::uint8_t> buffer;
  schema::encode_linestring(longer, 4326, buffer);
  EXPECT_EQ(buffer, schema::encode_linestring(longer, 4326));
  const std::uint8_t* storage = buffer.data();
  schema::encode_linestring(shorter, 32633, buffer);
  EXPECT_EQ(buffer, schema::encode_linestring(shorter, 32633));
  EXPECT_EQ(buffer.size(), 8u + 32u + 1u + 4u + 4u + 32u);
  EXPECT_EQ(buffer.data(), storage);
}

TEST(GpkgGeometry, PointRoundTrip) {
  const auto blob = schema::encode_point({1.5, -2.25}, 32633);
  EXPECT_EQ(blob.size(), 8u + 21u);  // no envelope for points
  const auto point = schema::decode_point(blob);
  ASSERT_TRUE(point.has_value());
  EXPECT_EQ(point->x, 1.5);
  EXPECT_EQ(point->y, -2.25);
  std::vector<schema::PlanePoint> out;
  EXPECT_FALSE(schema::decode_linestring(blob, out));  // a point is not a linestring
}

TEST(GpkgGeometry, RejectsMalformedBlobs) {
  const std::vector<schema::PlanePoint> points = {{0, 0}, {1, 1}};
  const auto good = schema::encode_linestring(points, 32633);
  std::vector<schema::PlanePoint> out;
  for (std::size_t length = 0; length < good.size(); ++length) {
    const std::vector<std::uint8_t> truncated(good.begin(),
                                              good.begin() + static_cast<long>(length));
    EXPECT_FALSE(schema::decode_linestring(truncated, out)) << "length " << length;
  }
  auto bad_magic = good;
  bad_magic[0] = 'X';
  EXPECT_FALSE(schema::decode_linestring(bad_magic, out));
  auto bad_type = good;
  bad_type[8 + 32 + 1] = 3;  // polygon
  EXPECT_FALSE(schema::decode_linestring(bad_type, out));
  auto big_count = good;
  big_count[8 + 32 + 5] = 0xff;  // claims far more points than present
  EXPECT_FALSE(schema::decode_linestring(big_count, out));
  auto extra = good;
  extra.push_back(0);
  EXPECT_FALSE(schema::decode_linestring(extra, out));
  auto bad_envelope = good;
  bad_envelope[3] = 0x0B;  // envelope code 5 does not exist
  EXPECT_FALSE(schema::decode_linestring(bad_envelope, out));
  const auto point = schema::encode_point({1, 2}, 1);
  for (std::size_t length = 0; length < point.size(); ++length) {
    const std::vector<std::uint8_t> truncated(point.begin(),
                                              point.begin() + static_cast<long>(length));
    EXPECT_FALSE(schema::decode_point(truncated).has_value()) << "length " << length;
  }
}

}  // namespace
