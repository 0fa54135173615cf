// Curvature of a road line: the circumradius at each vertex, measured over a baseline so that
// digitising jitter between dense vertices does not read as a sharp bend.
#pragma once

#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

/// Circumradius of the triangle a-b-c in metres:
///   r = |ab| |bc| |ca| / sqrt((p+q+s)(q+s-p)(p+s-q)(p+q-s)),
/// capped at `straight_radius_m` (collinear or degenerate triangles return it).
double circumradius_m(PlanePoint a, PlanePoint b, PlanePoint c, double straight_radius_m) noexcept;

/// Inserts points on edges longer than `max_spacing_m` (metres, > 0) so that no two
/// consecutive points are further apart. The original vertices are kept.
std::vector<PlanePoint> resample(const std::vector<PlanePoint>& line, double max_spacing_m);

struct CurvatureOptions {
  double baseline_m = 10.0;          ///< shortest arm of the triangle at a vertex, metres
  double straight_radius_m = 10000;  ///< radius of a straight line, metres
  bool closed = false;               ///< the line is a ring (last point == first point)
};

/// Radius at every point of `line` (metres). The triangle at vertex i uses the points at
/// arc distance max(baseline, distance to the neighbouring vertex) before and after it
/// (interpolated along the line), so that vertices drawn on an arc give the arc's radius
/// whether they are 2 m or 15 m apart. The ends of an open line get the straight radius.
std::vector<double> vertex_radii_m(const std::vector<PlanePoint>& line,
                                   const CurvatureOptions& options);

}  // namespace roadcross::preprocess
