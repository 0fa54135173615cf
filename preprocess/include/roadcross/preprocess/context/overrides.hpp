// Operator overrides: what the map does not know (a school entrance, a blind driveway), given
// as a GeoJSON FeatureCollection. Each feature selects segments by a Polygon/MultiPolygon
// geometry (WGS84 lon/lat, RFC 7946) and/or an `osm_way_id` property (a number or an array),
// and carries at least one effect:
//   context_delta  (integer) added to the segment's context score
//   no_crossing    (true)    the segment is never suitable (reason OVERRIDE)
//   force_suitable (true)    the segment is suitable whatever its score
//   note           (string)  why; listed per segment in override_note
// When both a geometry and osm_way_id are given, a segment must match both.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "roadcross/geo.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess {

/// A GeoJSON polygon: the outer ring first, then holes; each ring closed, lon/lat degrees.
using LonLatRing = std::vector<geo::LatLon>;
using LonLatPolygon = std::vector<LonLatRing>;

/// The longest note of one feature, bytes: a note says why, in a sentence; it is stored on every
/// segment the feature touches.
inline constexpr std::size_t kMaxOverrideNoteBytes = 500;
/// The longest override_note of one segment, bytes (the notes of all features touching it,
/// joined by "; "): longer is cut at a character boundary and ends in "...".
inline constexpr std::size_t kMaxSegmentNoteBytes = 2000;
/// The largest overrides file read, bytes.
inline constexpr std::size_t kMaxOverridesFileBytes = 64u << 20;
/// context_delta's range, points of the context score.
inline constexpr int kMaxContextDelta = 1000;
/// The context score after overrides is clamped to [-kMaxContextScore, kMaxContextScore], points
/// (far from int's limits, so that score + context_score cannot overflow either).
inline constexpr int kMaxContextScore = 1000000;

struct Override {
  std::string source;             ///< the file (or name) it was read from, for errors
  std::size_t feature_index = 0;  ///< position in the file's "features" array, from 0
  std::vector<LonLatPolygon> polygons;
  std::vector<std::int64_t> osm_way_ids;
  int context_delta = 0;  ///< in [-kMaxContextDelta, kMaxContextDelta]
  bool no_crossing = false;
  bool force_suitable = false;
  std::string note;  ///< the given note, or "override feature N"
};

/// Parses a GeoJSON text; throws InputError(`name`, "feature N: ...") on anything not
/// described above (unknown properties, wrong types, open or degenerate rings, ...).
std::vector<Override> parse_overrides(const std::string& text, const std::string& name);

/// Reads and parses a GeoJSON file (a regular file of at most kMaxOverridesFileBytes).
std::vector<Override> read_overrides(const std::string& path);

/// Does the segment polyline (UTM) touch the polygon (UTM rings, even-odd fill)?
bool polyline_touches_polygon(std::span<const PlanePoint> line,
                              const std::vector<std::vector<PlanePoint>>& rings);

/// Applies the overrides to the segments they select (context_score must be set already).
/// Returns, per override, how many segments it touched.
std::vector<std::uint64_t> apply_overrides(RoadGraph& graph,
                                           const std::vector<Override>& overrides);

}  // namespace roadcross::preprocess
