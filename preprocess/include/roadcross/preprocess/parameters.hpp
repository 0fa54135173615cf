// Every tunable of the build, in one self-validating structure (OSRM-style config structs).
// Each section lists its parameters once, as ParameterSpecs; the CLI flags, the parameter file,
// validation, --print-config and the DB metadata are all derived from those lists, so a new
// parameter is one field plus one line.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "roadcross/preprocess/context/context.hpp"
#include "roadcross/preprocess/geometry/geometry_cost.hpp"
#include "roadcross/preprocess/common/parameter_spec.hpp"
#include "roadcross/preprocess/rank.hpp"
#include "roadcross/preprocess/sight/sight.hpp"
#include "roadcross/preprocess/terrain/terrain.hpp"

namespace roadcross::preprocess {

/// Segmentation.
struct SegmentParameters {
  double max_segment_length_m = 10.0;
  void describe(std::vector<ParameterSpec>& out);
};

/// When a crossing place is suitable (docs/runtime.md, "Queries"); applied by the runtime, recorded
/// in the DB metadata with the rest.
struct SuitabilityParameters {
  double threshold = 20.0;         ///< suitable when score + context >= this
  double valid_distance_m = 10.0;  ///< a position is valid within this of a road centreline
  void describe(std::vector<ParameterSpec>& out);
};

struct Parameters {
  SegmentParameters segments;
  GeometryParameters geometry;
  TerrainParameters terrain;
  RankParameters rank;
  ContextParameters context;
  SightParameters sight;
  SuitabilityParameters suitability;

  /// All parameters, pointing into this object. Order is stable (it is the file order).
  std::vector<ParameterSpec> specs();
  std::vector<ParameterSpec> specs() const { return const_cast<Parameters*>(this)->specs(); }

  /// Throws ParameterError naming the first parameter out of range (section.name).
  void validate() const;
  /// ("param.<section>.<name>", value) pairs for the DB metadata, in specs() order.
  std::vector<std::pair<std::string, std::string>> as_metadata() const;
};

}  // namespace roadcross::preprocess
