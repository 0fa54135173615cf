// Strokes: a road as a driver sees it, independent of how OSM split it into ways. A stroke
// chains road pieces through graph nodes of degree 2 (where two ways merely join) and ends at
// junctions (degree >= 3) and dead ends. Windowed measures (curvature, terrain) run along
// strokes so that their value does not depend on way boundaries, and do not wander into side
// roads at junctions.
#pragma once

#include <cstddef>
#include <vector>

#include "roadcross/preprocess/segments.hpp"

namespace roadcross::preprocess {

struct StrokeSegment {
  std::size_t segment = 0;  ///< index into RoadGraph::segments
  bool reversed = false;    ///< the stroke runs against the segment's (the way's) direction
  double start_m = 0.0;     ///< position of the segment's stroke-first end along the stroke
  double end_m = 0.0;
};

struct Stroke {
  std::vector<PlanePoint> points;       ///< the stroke's line, joints not repeated
  std::vector<StrokeSegment> segments;  ///< in stroke order
  double length_m = 0.0;
  bool closed = false;  ///< a ring with no junction or dead end (e.g. an isolated roundabout)
};

/// Every piece belongs to exactly one stroke.
std::vector<Stroke> build_strokes(const RoadGraph& graph);

}  // namespace roadcross::preprocess
