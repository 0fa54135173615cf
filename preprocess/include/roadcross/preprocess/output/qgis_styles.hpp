// Default styles for QGIS, stored in the GeoPackage's layer_styles table (QGIS's convention:
// QGIS applies the row marked useAsDefault when it opens the layer).
#pragma once

#include <string>
#include <vector>

namespace roadcross::preprocess {

/// The map's default verdict parameters (the metadata the build records and the runtime reads):
/// what the stored `suitable` column is judged under.
struct SuitabilityRule {
  double threshold = 20.0;                    ///< param.suitability.threshold (score + context)
  bool limited_visibility_unsuitable = true;  ///< param.sight.limited_visibility_unsuitable
  double max_kerb_height_m = 1.0;             ///< param.suitability.max_kerb_height_m, metres
};

/// SQL that creates layer_styles (registered in gpkg_contents as an attributes table, which QGIS
/// needs to find it) with the default styles: segments suitable / not (default, by the stored
/// `suitable` column) and by rank,
/// crossings by kind, the terrain as a hillshade. `last_change` fills update_time (ISO 8601, so
/// that the output stays deterministic).
std::vector<std::string> qgis_style_statements(const std::string& last_change);

}  // namespace roadcross::preprocess
