// roadcross export: a feature table of the map as GeoJSON in WGS84 with every column as a
// property, plus the runtime's judgement of each segment (suitable, assess_reasons).
#pragma once

#include <optional>
#include <string>

#include "roadcross/viz/layers.hpp"

namespace roadcross::viz {

struct ExportOptions {
  std::string db_path;
  std::string output_path;
  std::string format = "geojson";
  std::string layer = "segments";  ///< "segments" or "crossings"
  std::optional<LonLatBox> bbox;
};

struct ExportSummary {
  std::size_t features = 0;
};

/// Writes the layer atomically. Throws std::runtime_error / std::invalid_argument.
ExportSummary export_features(const ExportOptions& options);

/// The same GeoJSON as a string (for the viewer).
std::string export_geojson_text(const ExportOptions& options, ExportSummary* summary = nullptr);

}  // namespace roadcross::viz
