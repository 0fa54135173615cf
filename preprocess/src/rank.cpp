#include "roadcross/preprocess/rank.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string_view>

namespace roadcross::preprocess {

void RankParameters::describe(std::vector<ParameterSpec>& out) {
  out.push_back({"rank", "curvature_weight", &curvature_weight, 0, 1000, false,
                 "weight of the curvature cost in the rank"});
  out.push_back({"rank", "class_weight", &class_weight, 0, 1000, false,
                 "weight of the road class cost in the rank"});
  out.push_back({"rank", "elevation_weight", &elevation_weight, 0, 1000, false,
                 "weight of the elevation cost in the rank"});
}

int rank_of(int curvature_cost, int class_cost, std::optional<int> elevation_cost,
            const RankParameters& p) noexcept {
  double weighted = p.curvature_weight * curvature_cost / 14.0 + p.class_weight * class_cost / 5.0;
  double total_weight = p.curvature_weight + p.class_weight;
  if (elevation_cost) {
    weighted += p.elevation_weight * *elevation_cost / 9.0;
    total_weight += p.elevation_weight;
  }
  if (!(total_weight > 0.0)) return 0;
  // The epsilon makes exact fractions (14/15 of the maximum) land on their rank, not below it.
  const double rank = std::floor(15.0 * weighted / total_weight + 1e-9);
  return static_cast<int>(std::clamp(rank, 0.0, 14.0));
}

void compute_rank(const RoadGraph& graph, Segment& s, const RankParameters& p) {
  // (Reasons need no sorting: ReasonSet keeps them in their canonical order.)
  s.rank = rank_of(s.curvature_cost.value_or(0), graph.class_cost(s).value_or(0),
                   s.elevation_cost.optional(), p);
}

void compute_ranks(RoadGraph& graph, const RankParameters& p) {
  for (Segment& s : graph.segments) compute_rank(graph, s, p);
}

}  // namespace roadcross::preprocess
