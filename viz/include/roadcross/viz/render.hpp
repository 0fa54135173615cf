// roadcross render: the map as a PNG, segments coloured by a cost term over a hillshade.
#pragma once

#include <optional>
#include <string>

#include "roadcross/viz/colors.hpp"
#include "roadcross/viz/layers.hpp"

namespace roadcross::viz {

struct RenderOptions {
  std::string db_path;
  /// The PNG: the map, with the legend, scale bar and attribution in a strip below it. A world
  /// file (.pgw) beside it georeferences the map (and the strip, as land south of it).
  std::string output_path;
  std::optional<LonLatBox> bbox;
  int width_px = 1200;
  ColorBy color_by = ColorBy::suitable;
  /// Street names along the roads where they fit (never over another name).
  bool street_names = true;
};

struct RenderSummary {
  int width_px = 0, height_px = 0;  ///< the whole picture
  int map_height_px = 0;            ///< the map above the legend strip
  double metres_per_px = 0.0;
  UtmBox area;  ///< the picture's extent in the map's UTM zone
  std::size_t segments = 0, crossings = 0;
  bool hillshade = false;
  std::size_t street_names = 0;  ///< names drawn (a long road may carry its name twice)
  std::string world_file;
};

/// Draws and writes the PNG (atomically). Throws std::runtime_error / std::invalid_argument.
RenderSummary render_png(const RenderOptions& options);

}  // namespace roadcross::viz
