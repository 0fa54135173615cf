// The GeoPackage geometry decoder (what the runtime reads from every segment and crossing row)
// on arbitrary blobs: false/nullopt or geometry that encodes back to a blob decoding the same.
#include <cstdlib>
#include <cstring>
#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace schema = roadcross::schema;

namespace {

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> blob(data, size);
  std::vector<schema::PlanePoint> line;
  // (encode_linestring needs two points; a shorter decoded line is checked by the readers)
  if (schema::decode_linestring(blob, line) && line.size() >= 2) {
    std::vector<schema::PlanePoint> again;
    if (!schema::decode_linestring(schema::encode_linestring(line, 32633), again) ||
        again.size() != line.size()) {
      std::abort();
    }
    for (std::size_t i = 0; i < line.size(); ++i) {
      if (!same_bits(line[i].x, again[i].x) || !same_bits(line[i].y, again[i].y)) std::abort();
    }
  }
  if (const auto point = schema::decode_point(blob)) {
    const auto again = schema::decode_point(schema::encode_point(*point, 32633));
    if (!again || !same_bits(again->x, point->x) || !same_bits(again->y, point->y)) std::abort();
  }
  return 0;
}
