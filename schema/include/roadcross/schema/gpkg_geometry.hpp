// GeoPackage geometry blobs (spec 1.3, clause 2.1.3): a "GP" header with the SRS id and an
// envelope, followed by little-endian WKB. Only what roadcross stores: 2D LINESTRING and POINT.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace roadcross::schema {

struct PlanePoint {
  double x = 0.0;  ///< easting in metres (UTM)
  double y = 0.0;  ///< northing in metres (UTM)
};

struct Envelope {
  double min_x = 0.0, max_x = 0.0, min_y = 0.0, max_y = 0.0;
};

Envelope envelope_of(std::span<const PlanePoint> points);

/// Encodes a LINESTRING with an XY envelope. `points` must hold at least two points.
std::vector<std::uint8_t> encode_linestring(std::span<const PlanePoint> points,
                                            std::int32_t srs_id);
/// The same into `out` (its contents replaced, its capacity kept: no allocation once it is
/// large enough).
void encode_linestring(std::span<const PlanePoint> points, std::int32_t srs_id,
                       std::vector<std::uint8_t>& out);

/// Encodes a POINT (no envelope, as the spec recommends for points).
std::vector<std::uint8_t> encode_point(PlanePoint point, std::int32_t srs_id);

/// Decodes a LINESTRING blob into `out` (cleared first). Returns false if the blob is not a
/// well-formed 2D GeoPackage LINESTRING; never reads past `blob`.
bool decode_linestring(std::span<const std::uint8_t> blob, std::vector<PlanePoint>& out);

/// Decodes a POINT blob.
std::optional<PlanePoint> decode_point(std::span<const std::uint8_t> blob);

}  // namespace roadcross::schema
