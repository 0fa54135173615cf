// Point-to-polyline geometry in a plane (UTM metres). Internal to the runtime.
#pragma once

#include <cstddef>
#include <span>

#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::detail {

using schema::PlanePoint;

struct PolylineProjection {
  PlanePoint closest;
  double distance_m = 0.0;
  std::size_t edge_index = 0;  ///< closest point lies on points[edge_index]..points[edge_index+1]
  double edge_fraction = 0.0;  ///< 0..1 along that edge
};

/// Nearest point of a polyline (>= 2 points) to `p`. Zero-length edges are skipped.
PolylineProjection project_onto_polyline(std::span<const PlanePoint> points, PlanePoint p) noexcept;

/// Direction (ENU yaw, radians) of the polyline at a projection: the edge's direction, or at an
/// interior vertex the bisector of the two edges that meet there, so the heading does not jump
/// when the query slides past a vertex of a bend.
double polyline_direction_rad(std::span<const PlanePoint> points,
                              const PolylineProjection& at) noexcept;

}  // namespace roadcross::detail
