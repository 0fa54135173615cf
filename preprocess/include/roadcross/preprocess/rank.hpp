// The rank (0 best .. 14 worst) and score (15 - rank) of a segment from its cost terms:
//   rank = min(14, floor(15 * (w_c * curvature/14 + w_k * class/5 + w_e * elevation/9) / W))
// with W = w_c + w_k + w_e, or W = w_c + w_k when the segment has no elevation cost. The thesis
// formula used (curvature+1)/15 and no clamp, which made rank 15 possible and rank 0
// impossible for anything but unclassified roads; docs/cost-model.md has the comparison.
#pragma once

#include <optional>
#include <vector>

#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess {

struct RankParameters {
  double curvature_weight = 70.0;  ///< thesis: 70 of 100
  double class_weight = 5.0;       ///< thesis: 5 of 100
  double elevation_weight = 25.0;  ///< thesis: 25 of 100

  void describe(std::vector<ParameterSpec>& out);
};

/// Rank 0..14 from curvature cost (0..14), class cost (0..5) and elevation cost (0..9, or none).
int rank_of(int curvature_cost, int class_cost, std::optional<int> elevation_cost,
            const RankParameters& p) noexcept;

/// Fills rank and score of every segment (run after every cost stage); puts the reasons in
/// canonical order.
void compute_ranks(RoadGraph& graph, const RankParameters& parameters);
/// The same for one segment of `graph` (its terms do not change after the cost stages).
void compute_rank(const RoadGraph& graph, Segment& segment, const RankParameters& parameters);

}  // namespace roadcross::preprocess
