// Crossing cost from the road's geometry: road class, distance to the nearest junction along
// the road, curvature (radius, level, windowed cost), and the reasons they imply
// (NOT_CROSSABLE_CLASS, TUNNEL, NEAR_JUNCTION, SHARP_BEND). docs/cost-model.md explains each
// term and where it differs from the thesis.
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess {

struct GeometryParameters {
  // Road class cost (the thesis' code, docs/cost-model.md): primary 5, secondary 4, tertiary/busway 3,
  // residential/living_street/service/road 2, unclassified 1; links as their road.
  double class_cost_primary = 5, class_cost_secondary = 4, class_cost_tertiary = 3;
  double class_cost_minor = 2, class_cost_unclassified = 1;
  /// A segment whose midpoint is closer than this to a junction along the road, metres.
  double near_junction_m = 15.0;
  /// Curvature samples: the OSM vertices plus straight points inserted so that no two samples
  /// are further apart, metres (thesis: 20 m).
  double resample_spacing_m = 20.0;
  /// Shortest and longest arm of the triangle whose circumradius is the radius at a vertex,
  /// metres (the arms reach to the neighbouring OSM vertices, within these limits).
  double curvature_baseline_m = 10.0;
  double curvature_max_arm_m = 50.0;
  /// Radius given to straight (collinear) stretches, metres (thesis: 10 000).
  double straight_radius_m = 10000.0;
  /// Radius limits of curvature levels 4, 3, 2, 1 (level 5 is a junction end), metres.
  double level4_radius_m = 40, level3_radius_m = 90, level2_radius_m = 150, level1_radius_m = 220;
  /// Weight of each curvature level 0..5 in the windowed cost.
  std::array<double, 6> level_weight = {0.75, 3, 6, 10, 20, 30};
  /// Half length of the window along the road, metres, and the weight of the own segment.
  double window_half_length_m = 100.0;
  double own_segment_weight = 3.0;
  /// SHARP_BEND below this radius, metres (the limit of curvature level 3).
  double sharp_bend_radius_m = 90.0;

  void describe(std::vector<ParameterSpec>& out);
  /// Checks what single ranges cannot: the level radii do not increase from level 4 to level 1.
  /// Throws ParameterError naming the parameter.
  void validate_relations() const;
};

/// Class cost of a highway=* value (motorway and trunk get the primary cost; they are never
/// suitable anyway). Returns 0 for a class that is not a kept road.
int class_cost(std::string_view highway, const GeometryParameters& parameters) noexcept;

/// Curvature level 0..5 of a segment from its radius and whether an end is at a junction.
int curvature_level(double radius_m, bool at_junction,
                    const GeometryParameters& parameters) noexcept;

struct Stroke;

/// The windowed curvature cost of every segment of `stroke` from the curvature levels already
/// set on the segments: sum(length * weight) / sum(length) over the road within
/// +-window_half_length_m of the segment's midpoint along the stroke (the segment itself counted
/// own_segment_weight times), floored and clamped to 0..14.
void assign_curvature_costs(RoadGraph& graph, const Stroke& stroke,
                            const GeometryParameters& parameters);

/// Fills class_cost, junction_distance_m, radius_m, curvature_level and curvature_cost of every
/// segment and appends NOT_CROSSABLE_CLASS, TUNNEL, NEAR_JUNCTION and SHARP_BEND.
void compute_geometry_costs(RoadGraph& graph, const GeometryParameters& parameters);

}  // namespace roadcross::preprocess
