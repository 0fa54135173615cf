// Strokes: a road as a driver sees it, independent of how OSM split it into ways. A stroke
// chains road pieces through graph nodes of degree 2 (where two ways merely join) and ends at
// junctions (degree >= 3) and dead ends. Windowed measures (curvature, terrain) run along
// strokes so that their value does not depend on way boundaries, and do not wander into side
// roads at junctions.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "roadcross/preprocess/graph/segments.hpp"

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

/// The strokes of build_strokes(), in the same order, one at a time: `visit` may change the
/// segments' cost fields (not their offsets and lengths, which the strokes are built from).
/// Holds one stroke at a time (all of them take ~40 bytes a segment).
void for_each_stroke(const RoadGraph& graph, const std::function<void(const Stroke&)>& visit);

/// The strokes of for_each_stroke(), built and visited on every core: batches of strokes (a few
/// thousand segments) run in parallel while this thread finds the next batch's pieces.
/// `incidences` are the graph's. `visit` may write only its own stroke's segments' fields, and
/// read no field another stroke's visit writes; it must not depend on the order of the strokes.
void for_each_stroke_parallel(const RoadGraph& graph, const Incidences& incidences,
                              const std::function<void(const Stroke&)>& visit);

/// Windowed mean along a stroke, for every segment of it (in stroke order): the
/// length-weighted mean of `values` (one per stroke segment, in stroke order) over the road
/// within +-half_length_m of the segment's midpoint, the segment itself counted `own_weight`
/// times. NaN values are skipped; a window without any value gives NaN. On a ring the window
/// continues past the closing point.
std::vector<double> windowed_mean(const Stroke& stroke, const std::vector<double>& values,
                                  double half_length_m, double own_weight);

}  // namespace roadcross::preprocess
