// What blocks a line of sight (issue 11): one edge of an obstacle's footprint. Its own header,
// below both the sight stage (sight.hpp) and its edge grid (edge_grid.hpp), so that the grid
// needs nothing of the stage.
#pragma once

#include "roadcross/schema/gpkg_geometry.hpp"

namespace roadcross::preprocess {

using schema::PlanePoint;

/// One edge of an obstacle's footprint (a building outline or a wall line), UTM metres, with
/// the opaque band above the local ground: from bottom_m (0, or min_height for a building on
/// pillars or over a passage) to top_m (metres above the ground, bottom_m <= top_m).
struct ObstacleEdge {
  PlanePoint a, b;
  float bottom_m = 0.0f, top_m = 0.0f;
};

}  // namespace roadcross::preprocess
