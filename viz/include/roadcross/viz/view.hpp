// roadcross view: a static, offline HTML page of the map (vendored Leaflet, no tiles).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "roadcross/viz/layers.hpp"

namespace roadcross::viz {

struct ViewOptions {
  std::string db_path;
  std::string output_dir;
  std::optional<LonLatBox> bbox;
};

struct ViewSummary {
  std::vector<std::string> files;  ///< written, relative to output_dir
  std::size_t segments = 0, crossings = 0;
};

/// Writes index.html, its script, style, data and the map library into output_dir (created
/// when missing). Throws std::runtime_error / std::invalid_argument.
ViewSummary write_view(const ViewOptions& options);

}  // namespace roadcross::viz
