// Curvature of a road line: the circumradius at each vertex, measured over a baseline so that
// digitising jitter between dense vertices does not read as a sharp bend, and reaching to the
// real neighbouring vertices (up to a maximum arm) so that a gentle curve drawn with sparse
// vertices does not either.
#pragma once

#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

/// Circumradius of the triangle a-b-c in metres:
///   r = |ab| |bc| |ca| / sqrt((p+q+s)(q+s-p)(p+s-q)(p+q-s)),
/// capped at `straight_radius_m` (collinear or degenerate triangles return it).
double circumradius_m(PlanePoint a, PlanePoint b, PlanePoint c, double straight_radius_m) noexcept;

struct CurvatureOptions {
  double baseline_m = 10.0;          ///< shortest arm of the triangle at a vertex, metres
  double straight_radius_m = 10000;  ///< radius of a straight line, metres
  bool closed = false;               ///< the line is a ring (last point == first point)
  double max_arm_m = 50.0;           ///< longest arm of the triangle at a vertex, metres
};

/// Radius at every point of `line` (metres). The triangle at vertex i uses the points at arc
/// distance clamp(distance to the neighbouring vertex, baseline, max arm) before and after it
/// (interpolated along the line), so that vertices drawn on an arc give the arc's radius whether
/// they are 2 m or 40 m apart. The ends of an open line get the straight radius.
std::vector<double> vertex_radii_m(const std::vector<PlanePoint>& line,
                                   const CurvatureOptions& options);

/// Radius along a line, sampled at its vertices (vertex_radii_m) and at points inserted on its
/// edges so that no two samples are more than `max_spacing_m` apart; the inserted points lie on
/// a straight edge and get the straight radius.
struct RadiusProfile {
  std::vector<double> position_m;  ///< arc length from the line's start, increasing
  std::vector<double> radius_m;
};
RadiusProfile radius_profile(const std::vector<PlanePoint>& line, const CurvatureOptions& options,
                             double max_spacing_m);

}  // namespace roadcross::preprocess
