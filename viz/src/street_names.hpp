// Street names along their roads in the PNG, where they fit.
#pragma once

#include <cairo.h>

#include <cstddef>
#include <functional>
#include <vector>

#include "roadcross/viz/layers.hpp"

namespace roadcross::viz {

/// A point of the picture, pixels (x east, y south).
struct PixelPoint {
  double x = 0.0, y = 0.0;
};

/// Where street names may go and how large they are.
struct NameLayout {
  double font_px = 11.0;      ///< font size, pixels, > 0
  double width_px = 0.0;      ///< the map's width; a name stays inside [0, width_px]
  double height_px = 0.0;     ///< the map's height (the legend strip below is not map)
  double max_turn_rad = 0.5;  ///< the most the road may turn under one name, radians, > 0
};

/// Draws each named road's name along it (glyph by glyph, upright, with a white halo) where the
/// road is long and straight enough to carry it; a name that would overlap one already drawn is
/// skipped. Segments of the same name that meet at a graph node form one road. `to_px` maps
/// UTM metres to pixels. Returns how many names were drawn.
std::size_t draw_street_names(cairo_t* cr, const std::vector<SegmentLayer>& segments,
                              const std::function<PixelPoint(const schema::PlanePoint&)>& to_px,
                              const NameLayout& layout);

}  // namespace roadcross::viz
