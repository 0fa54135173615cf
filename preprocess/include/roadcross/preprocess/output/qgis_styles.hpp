// Default styles for QGIS, stored in the GeoPackage's layer_styles table (QGIS's convention:
// QGIS applies the row marked useAsDefault when it opens the layer).
#pragma once

#include <string>
#include <vector>

namespace roadcross::preprocess {

/// What the segments' "suitable" style needs from the map's parameters: the runtime's verdict at
/// a point on a segment under the map's default thresholds.
struct SuitabilityRule {
  double threshold = 0.0;                     ///< param.suitability.threshold (score + context)
  bool limited_visibility_unsuitable = true;  ///< param.sight.limited_visibility_unsuitable
};

/// QGIS expression of the runtime's verdict (runtime/src/assess.cpp: suitable = not forbidden
/// and (score + context >= threshold and not hidden, or forced)) for a point on the segment.
std::string suitable_expression(const SuitabilityRule& rule);

/// SQL that creates layer_styles (registered in gpkg_contents as an attributes table, which QGIS
/// needs to find it) with the default styles: segments suitable / not (default) and by rank,
/// crossings by kind, the terrain as a hillshade. `last_change` fills update_time (ISO 8601, so
/// that the output stays deterministic).
std::vector<std::string> qgis_style_statements(const SuitabilityRule& rule,
                                               const std::string& last_change);

}  // namespace roadcross::preprocess
