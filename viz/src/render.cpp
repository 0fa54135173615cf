// The PNG cost map, drawn with Cairo in the map's UTM grid (north up, metres to pixels by one
// scale), so that a world file makes it a georeferenced raster for QGIS or GDAL.
#include "roadcross/viz/render.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "hillshade.hpp"
#include "roadcross/files/atomic_file.hpp"
#include "roadcross/geo.hpp"
#include "street_names.hpp"

namespace roadcross::viz {

namespace {

constexpr int kMinWidthPx = 200;
constexpr int kMaxSidePx = 10000;
constexpr double kPaddingFraction = 0.04;  // a margin so that no line ends at the frame
constexpr const char* kAttribution = "\u00a9 OpenStreetMap contributors";
constexpr const char* kFont = "DejaVu Sans";

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

// Metres to pixels: x grows east, y grows south.
struct Frame {
  UtmBox area;
  double metres_per_px = 1.0;
  int width_px = 0, height_px = 0;
  double x(double e) const { return (e - area.min_e_m) / metres_per_px; }
  double y(double n) const { return (area.max_n_m - n) / metres_per_px; }
  double ui = 1.0;  // size of UI elements relative to a 1200 px wide picture
};

Frame make_frame(const UtmBox& shown, int width_px) {
  if (width_px < kMinWidthPx || width_px > kMaxSidePx) {
    throw std::invalid_argument("--width must be in " + std::to_string(kMinWidthPx) + ".." +
                                std::to_string(kMaxSidePx) + " pixels");
  }
  const double pad = kPaddingFraction * std::max({shown.width_m(), shown.height_m(), 50.0});
  Frame f;
  f.area = {shown.min_e_m - pad, shown.min_n_m - pad, shown.max_e_m + pad, shown.max_n_m + pad};
  f.width_px = width_px;
  f.metres_per_px = f.area.width_m() / width_px;
  f.height_px = static_cast<int>(std::lround(f.area.height_m() / f.metres_per_px));
  if (f.height_px > kMaxSidePx) {
    throw std::invalid_argument("the picture would be " + std::to_string(f.height_px) +
                                " px tall; give a smaller --width or a wider --bbox");
  }
  f.height_px = std::max(f.height_px, 1);
  f.area.min_n_m = f.area.max_n_m - f.height_px * f.metres_per_px;
  f.ui = width_px / 1200.0;
  return f;
}

void set_color(cairo_t* cr, const Rgb& c, double alpha = 1.0) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

bool draw_hillshade(cairo_t* cr, const Frame& f, const std::string& db_path) {
  std::optional<ShadeImage> shade = hillshade(db_path, f.area);
  if (!shade) return false;
  const int stride = cairo_format_stride_for_width(CAIRO_FORMAT_ARGB32, shade->width);
  if (stride != shade->width * 4) throw std::runtime_error("unexpected Cairo stride");
  SurfacePtr image(
      cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(shade->argb.data()),
                                          CAIRO_FORMAT_ARGB32, shade->width, shade->height, stride),
      cairo_surface_destroy);
  cairo_save(cr);
  cairo_translate(cr, f.x(shade->west_m), f.y(shade->north_m));
  const double scale = shade->cell_m / f.metres_per_px;
  cairo_scale(cr, scale, scale);
  cairo_set_source_surface(cr, image.get(), 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_BILINEAR);
  // Faint, so that the coloured network stays the first thing the eye reads.
  cairo_paint_with_alpha(cr, 0.45);
  cairo_restore(cr);
  return true;
}

void trace(cairo_t* cr, const Frame& f, const SegmentLayer& s) {
  cairo_new_path(cr);
  for (const schema::PlanePoint& p : s.line) cairo_line_to(cr, f.x(p.x), f.y(p.y));
}

void draw_segments(cairo_t* cr, const Frame& f, const std::vector<SegmentLayer>& segments,
                   const ColorScale& scale) {
  const double width = std::max(2.0, 3.0 * f.ui);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  // A white casing under every line keeps colours readable over the hillshade.
  cairo_set_line_width(cr, width + 2.0 * f.ui);
  cairo_set_source_rgb(cr, 1, 1, 1);
  for (const SegmentLayer& s : segments) {
    trace(cr, f, s);
    cairo_stroke(cr);
  }
  cairo_set_line_width(cr, width);
  for (const SegmentLayer& s : segments) {
    set_color(cr, scale.color_of(s.assessment, s.deciding_reason));
    trace(cr, f, s);
    cairo_stroke(cr);
  }
}

double crossing_radius(const Frame& f) {
  return std::max(2.5, 3.5 * f.ui);
}

void crossing_symbol(cairo_t* cr, double x, double y, double radius, double ui) {
  cairo_new_path(cr);
  cairo_arc(cr, x, y, radius, 0, 2 * M_PI);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_fill_preserve(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, std::max(1.0, 1.2 * ui));
  cairo_stroke(cr);
}

void draw_crossings(cairo_t* cr, const Frame& f, const std::vector<CrossingLayer>& crossings) {
  for (const CrossingLayer& c : crossings) {
    if (c.designated) crossing_symbol(cr, f.x(c.point.x), f.y(c.point.y), crossing_radius(f), f.ui);
  }
}

void font(cairo_t* cr, double size, bool bold = false) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
}

double text_width(cairo_t* cr, const std::string& text) {
  cairo_text_extents_t e;
  cairo_text_extents(cr, text.c_str(), &e);
  return e.x_advance;
}

void panel(cairo_t* cr, double x, double y, double w, double h) {
  cairo_rectangle(cr, x, y, w, h);
  cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
  cairo_fill_preserve(cr);
  cairo_set_source_rgba(cr, 0, 0, 0, 0.6);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
}

// The legend, scale bar and attribution sit in a strip below the map, so that they never hide
// a segment. Legend entries flow in columns of kLegendRows.
constexpr int kLegendRows = 4;

struct Strip {
  double top = 0.0;  ///< y of the strip's top edge (the map's bottom)
  double size = 14.0, line = 21.0, pad = 10.0;
  double height() const { return 2 * pad + line * (1 + kLegendRows) + 0.9 * line; }
};

Strip strip_for(const Frame& f) {
  Strip strip;
  strip.top = f.height_px;
  strip.size = std::max(9.0, 14.0 * f.ui);  // still legible on a small picture
  strip.line = 1.5 * strip.size;
  strip.pad = 0.7 * strip.size;
  return strip;
}

void draw_legend(cairo_t* cr, const Frame& f, const Strip& st, const ColorScale& scale,
                 std::vector<LegendEntry> entries, bool hillshade) {
  const double swatch = 2.2 * st.size;
  entries.push_back({"designated crossing", Rgb{}});  // drawn as the crossing symbol
  font(cr, st.size);
  double column_w = 0;
  for (const LegendEntry& e : entries) column_w = std::max(column_w, text_width(cr, e.label));
  column_w += swatch + 3 * st.pad;
  font(cr, st.size, true);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_move_to(cr, st.pad, st.top + st.pad + st.size);
  cairo_show_text(cr, scale.title().c_str());
  font(cr, st.size);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double x = st.pad + static_cast<double>(i / kLegendRows) * column_w;
    const double y = st.top + st.pad + st.size + st.line * static_cast<double>(1 + i % kLegendRows);
    const double mid = y - 0.35 * st.size;
    if (i + 1 == entries.size()) {
      crossing_symbol(cr, x + swatch / 2, mid, crossing_radius(f), f.ui);
    } else {
      cairo_set_line_width(cr, std::max(2.0, 4.0 * f.ui));
      set_color(cr, entries[i].color);
      cairo_move_to(cr, x, mid);
      cairo_line_to(cr, x + swatch, mid);
      cairo_stroke(cr);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_move_to(cr, x + swatch + st.pad, y);
    cairo_show_text(cr, entries[i].label.c_str());
  }
  if (hillshade) {
    font(cr, 0.8 * st.size);
    cairo_move_to(cr, st.pad, st.top + st.height() - st.pad);
    cairo_show_text(cr, "over a hillshade of the terrain (sun from the north-west)");
  }
}

// 1, 2 or 5 times a power of ten, at most `limit`.
double round_length_m(double limit) {
  const double power = std::pow(10.0, std::floor(std::log10(limit)));
  for (double step : {5.0, 2.0, 1.0})
    if (step * power <= limit) return step * power;
  return power;
}

// Right-aligned in the strip, above the attribution.
void draw_scale_bar(cairo_t* cr, const Frame& f, const Strip& st) {
  const double length_m = round_length_m(f.width_px * f.metres_per_px / 5.0);
  const double length_px = length_m / f.metres_per_px, bar = 6 * f.ui;
  char label[32];
  if (length_m >= 1000) {
    std::snprintf(label, sizeof label, "%g km", length_m / 1000);
  } else {
    std::snprintf(label, sizeof label, "%g m", length_m);
  }
  font(cr, st.size);
  const double x0 = f.width_px - st.pad - length_px - text_width(cr, label) - 8 * f.ui;
  const double y0 = st.top + st.pad + st.line;
  for (int i = 0; i < 4; ++i) {
    cairo_rectangle(cr, x0 + i * length_px / 4, y0, length_px / 4, bar);
    if (i % 2 == 0) {
      cairo_set_source_rgb(cr, 0, 0, 0);
    } else {
      cairo_set_source_rgb(cr, 1, 1, 1);
    }
    cairo_fill(cr);
  }
  cairo_rectangle(cr, x0, y0, length_px, bar);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 1.0);
  cairo_stroke(cr);
  cairo_move_to(cr, x0 - text_width(cr, "0") / 2, y0 - 4 * f.ui);
  cairo_show_text(cr, "0");
  cairo_move_to(cr, x0 + length_px + 6 * f.ui, y0 + bar);
  cairo_show_text(cr, label);
}

// The arrow points to true north, which differs from the grid's up by the convergence.
void draw_north_arrow(cairo_t* cr, const Frame& f, const MapInfo& info) {
  const double e = (f.area.min_e_m + f.area.max_e_m) / 2, n = (f.area.min_n_m + f.area.max_n_m) / 2;
  const geo::LatLon centre = geo::utm_to_wgs84(e, n, info.zone);
  const double convergence =
      geo::wgs84_to_utm(centre.lat_deg, centre.lon_deg, info.zone).convergence_rad;
  const double size = 30 * f.ui, cx = f.width_px - 35 * f.ui, cy = 45 * f.ui;
  panel(cr, cx - 25 * f.ui, cy - 38 * f.ui, 50 * f.ui, 70 * f.ui);
  cairo_save(cr);
  cairo_translate(cr, cx, cy);
  cairo_rotate(cr, convergence);  // grid yaw of true north is pi/2 - convergence
  cairo_move_to(cr, 0, -size / 2 - 4 * f.ui);
  cairo_line_to(cr, size / 3, size / 2);
  cairo_line_to(cr, 0, size / 4);
  cairo_line_to(cr, -size / 3, size / 2);
  cairo_close_path(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_fill(cr);
  cairo_restore(cr);
  font(cr, 13 * f.ui, true);
  cairo_move_to(cr, cx - text_width(cr, "N") / 2, cy + 28 * f.ui);
  cairo_show_text(cr, "N");
}

void draw_attribution(cairo_t* cr, const Frame& f, const Strip& st, const MapInfo& info) {
  const std::string text =
      std::string(kAttribution) + "  |  roadcross, EPSG:" + std::to_string(info.epsg);
  font(cr, 0.9 * st.size);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_move_to(cr, f.width_px - st.pad - text_width(cr, text), st.top + st.height() - st.pad);
  cairo_show_text(cr, text.c_str());
}

// The scale, and the values present in the map that its legend lists: the landform classes
// for landform, the deciding reasons for reason.
ColorScale scale_for(const MapLayers& layers, ColorBy by, std::vector<std::string>& present) {
  int context_min = 0, context_max = 1;
  bool first = true;
  const auto note = [&](const std::string& value) {
    if (std::find(present.begin(), present.end(), value) == present.end()) present.push_back(value);
  };
  for (const SegmentLayer& s : layers.segments) {
    const Assessment& a = s.assessment;
    if (by == ColorBy::landform && a.landform) note(*a.landform);
    if (by == ColorBy::reason) note(s.deciding_reason);
    if (!a.context_score) continue;
    context_min = first ? *a.context_score : std::min(context_min, *a.context_score);
    context_max = first ? *a.context_score : std::max(context_max, *a.context_score);
    first = false;
  }
  const double threshold = layers.segments.empty() ? 20.0 : layers.segments[0].assessment.threshold;
  return ColorScale(by, threshold, context_min, context_max);
}

// A world file: the PNG becomes a georeferenced raster in the map's UTM CRS.
std::string write_world_file(const std::string& png_path, const Frame& f) {
  std::string path = png_path;
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) path.resize(dot);
  path += ".pgw";
  char text[256];
  std::snprintf(text, sizeof text, "%.6f\n0\n0\n%.6f\n%.6f\n%.6f\n", f.metres_per_px,
                -f.metres_per_px, f.area.min_e_m + f.metres_per_px / 2,
                f.area.max_n_m - f.metres_per_px / 2);
  files::write_file_atomically(path, text);
  return path;
}

}  // namespace

RenderSummary render_png(const RenderOptions& options) {
  files::check_output_path(options.output_path);
  const MapLayers layers = load_layers(options.db_path, options.bbox);
  const Frame f = make_frame(layers.area, options.width_px);
  const Strip strip = strip_for(f);
  const int image_height_px = f.height_px + static_cast<int>(std::ceil(strip.height()));
  SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, f.width_px, image_height_px),
                     cairo_surface_destroy);
  ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);
  cairo_paint(cr.get());
  RenderSummary summary;
  summary.hillshade = layers.has_terrain && draw_hillshade(cr.get(), f, options.db_path);
  std::vector<std::string> present;
  const ColorScale scale = scale_for(layers, options.color_by, present);
  draw_segments(cr.get(), f, layers.segments, scale);
  draw_crossings(cr.get(), f, layers.crossings);
  if (options.street_names) {
    const NameLayout names{std::max(9.0, 11.0 * f.ui), static_cast<double>(f.width_px),
                           static_cast<double>(f.height_px)};
    summary.street_names = draw_street_names(
        cr.get(), layers.segments,
        [&](const schema::PlanePoint& p) {
          return PixelPoint{f.x(p.x), f.y(p.y)};
        },
        names);
  }
  cairo_rectangle(cr.get(), 0, strip.top, f.width_px, strip.height() + 1);
  cairo_set_source_rgb(cr.get(), 1, 1, 1);  // the strip covers what lies beyond the map
  cairo_fill(cr.get());
  cairo_move_to(cr.get(), 0, strip.top + 0.5);
  cairo_line_to(cr.get(), f.width_px, strip.top + 0.5);
  cairo_set_source_rgb(cr.get(), 0.4, 0.4, 0.4);
  cairo_set_line_width(cr.get(), 1.0);
  cairo_stroke(cr.get());
  draw_legend(cr.get(), f, strip, scale, scale.legend(present), summary.hillshade);
  draw_scale_bar(cr.get(), f, strip);
  draw_north_arrow(cr.get(), f, layers.info);
  draw_attribution(cr.get(), f, strip, layers.info);
  cairo_surface_flush(surface.get());

  files::AtomicFile png(options.output_path);
  if (cairo_surface_write_to_png(surface.get(), png.temp_path().c_str()) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error("cannot write " + options.output_path);
  }
  png.commit();
  summary.world_file = write_world_file(options.output_path, f);
  summary.width_px = f.width_px;
  summary.height_px = image_height_px;
  summary.map_height_px = f.height_px;
  summary.metres_per_px = f.metres_per_px;
  summary.area = f.area;
  summary.segments = layers.segments.size();
  summary.crossings =
      static_cast<std::size_t>(std::count_if(layers.crossings.begin(), layers.crossings.end(),
                                             [](const auto& c) { return c.designated; }));
  return summary;
}

}  // namespace roadcross::viz
