#include "roadcross/schema/gpkg_geometry.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

namespace roadcross::schema {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the blob codec writes native doubles as little-endian WKB");

constexpr std::uint8_t kFlagsLittleEndianXyEnvelope = 0x03;  // envelope code 1, byte order 1
constexpr std::uint8_t kFlagsLittleEndianNoEnvelope = 0x01;
constexpr std::uint32_t kWkbPoint = 1;
constexpr std::uint32_t kWkbLineString = 2;

template <typename T>
void append(std::vector<std::uint8_t>& out, T value) {
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

template <typename T>
bool read(std::span<const std::uint8_t> blob, std::size_t& offset, T& value) {
  if (offset + sizeof(T) > blob.size()) return false;
  std::memcpy(&value, blob.data() + offset, sizeof(T));
  offset += sizeof(T);
  return true;
}

void append_header(std::vector<std::uint8_t>& out, std::uint8_t flags, std::int32_t srs_id) {
  // push_back rather than insert({...}): g++ 12 warns falsely (-Wstringop-overflow) on the latter.
  out.push_back('G');
  out.push_back('P');
  out.push_back(0);  // version 1
  out.push_back(flags);
  append(out, srs_id);
}

/// Checks the GP header and returns the offset of the WKB, or 0 if malformed.
std::size_t wkb_offset(std::span<const std::uint8_t> blob) {
  if (blob.size() < 8 || blob[0] != 'G' || blob[1] != 'P' || blob[2] != 0) return 0;
  const std::uint8_t flags = blob[3];
  if ((flags & 0x01) == 0) return 0;  // big-endian header: roadcross never writes it
  static constexpr std::size_t kEnvelopeBytes[] = {0, 32, 48, 48, 64};
  const unsigned envelope_code = (flags >> 1) & 0x07;
  if (envelope_code > 4) return 0;
  return 8 + kEnvelopeBytes[envelope_code];
}

}  // namespace

Envelope envelope_of(std::span<const PlanePoint> points) {
  Envelope e{points.front().x, points.front().x, points.front().y, points.front().y};
  for (const PlanePoint& p : points) {
    e.min_x = std::min(e.min_x, p.x);
    e.max_x = std::max(e.max_x, p.x);
    e.min_y = std::min(e.min_y, p.y);
    e.max_y = std::max(e.max_y, p.y);
  }
  return e;
}

std::vector<std::uint8_t> encode_linestring(std::span<const PlanePoint> points,
                                            std::int32_t srs_id) {
  std::vector<std::uint8_t> out;
  encode_linestring(points, srs_id, out);
  return out;
}

void encode_linestring(std::span<const PlanePoint> points, std::int32_t srs_id,
                       std::vector<std::uint8_t>& out) {
  out.clear();
  out.reserve(8 + 32 + 9 + points.size() * 16);
  append_header(out, kFlagsLittleEndianXyEnvelope, srs_id);
  const Envelope e = envelope_of(points);
  append(out, e.min_x);
  append(out, e.max_x);
  append(out, e.min_y);
  append(out, e.max_y);
  out.push_back(1);  // WKB little-endian
  append(out, kWkbLineString);
  append(out, static_cast<std::uint32_t>(points.size()));
  for (const PlanePoint& p : points) {
    append(out, p.x);
    append(out, p.y);
  }
}

std::vector<std::uint8_t> encode_point(PlanePoint point, std::int32_t srs_id) {
  std::vector<std::uint8_t> out;
  append_header(out, kFlagsLittleEndianNoEnvelope, srs_id);
  out.push_back(1);
  append(out, kWkbPoint);
  append(out, point.x);
  append(out, point.y);
  return out;
}

bool decode_linestring(std::span<const std::uint8_t> blob, std::vector<PlanePoint>& out) {
  out.clear();
  std::size_t offset = wkb_offset(blob);
  if (offset == 0 || offset >= blob.size() || blob[offset] != 1) return false;
  ++offset;
  std::uint32_t type = 0, count = 0;
  if (!read(blob, offset, type) || type != kWkbLineString) return false;
  if (!read(blob, offset, count) || count < 2) return false;
  if (blob.size() - offset != std::size_t{count} * 16) return false;
  out.resize(count);
  std::memcpy(out.data(), blob.data() + offset, std::size_t{count} * 16);
  return true;
}

std::optional<PlanePoint> decode_point(std::span<const std::uint8_t> blob) {
  std::size_t offset = wkb_offset(blob);
  if (offset == 0 || offset >= blob.size() || blob[offset] != 1) return std::nullopt;
  ++offset;
  std::uint32_t type = 0;
  PlanePoint p;
  if (!read(blob, offset, type) || type != kWkbPoint) return std::nullopt;
  if (!read(blob, offset, p.x) || !read(blob, offset, p.y)) return std::nullopt;
  return p;
}

}  // namespace roadcross::schema
