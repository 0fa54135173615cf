// Street names along their roads: the named segments are joined into roads (same name, shared
// graph node), and a name is set glyph by glyph along its road where the road is long and
// straight enough, upright, never over another name.
#include "street_names.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>
#include <unordered_map>

namespace roadcross::viz {

namespace {

using Road = std::vector<PixelPoint>;

// Joins the segments of one name into roads: walks from every node where the named roads do not
// simply continue (an end or a fork), then around what is left (closed loops).
std::vector<Road> roads_of(const std::vector<const SegmentLayer*>& named,
                           const std::function<PixelPoint(const schema::PlanePoint&)>& to_px) {
  std::unordered_map<std::int64_t, std::vector<std::size_t>> at_node;
  for (std::size_t i = 0; i < named.size(); ++i) {
    at_node[named[i]->from_node_id].push_back(i);
    at_node[named[i]->to_node_id].push_back(i);
  }
  std::vector<bool> used(named.size(), false);
  std::vector<Road> roads;
  const auto walk = [&](std::size_t first, std::int64_t from_node) {
    Road road;
    std::size_t i = first;
    std::int64_t node = from_node;
    while (!used[i]) {
      used[i] = true;
      const SegmentLayer& s = *named[i];
      const bool forward = s.from_node_id == node;
      std::vector<schema::PlanePoint> line = s.line;
      if (!forward) std::reverse(line.begin(), line.end());
      for (std::size_t k = road.empty() ? 0 : 1; k < line.size(); ++k)
        road.push_back(to_px(line[k]));
      node = forward ? s.to_node_id : s.from_node_id;
      const std::vector<std::size_t>& next = at_node[node];
      if (next.size() != 2) break;  // an end or a fork: the road stops here
      i = next[0] == i ? next[1] : next[0];
    }
    roads.push_back(std::move(road));
  };
  for (const auto& [node, members] : at_node) {
    if (members.size() == 2) continue;
    for (std::size_t i : members) {
      if (!used[i]) walk(i, node);
    }
  }
  for (std::size_t i = 0; i < named.size(); ++i) {
    if (!used[i]) walk(i, named[i]->from_node_id);
  }
  return roads;
}

// A road measured along its length.
class Path {
 public:
  explicit Path(const Road& road) : points_(road), along_(road.size(), 0.0) {
    for (std::size_t i = 1; i < points_.size(); ++i) {
      along_[i] = along_[i - 1] +
                  std::hypot(points_[i].x - points_[i - 1].x, points_[i].y - points_[i - 1].y);
    }
  }
  double length() const { return along_.empty() ? 0.0 : along_.back(); }

  /// The point `distance` along the road and the road's direction there (atan2 in pixels).
  std::pair<PixelPoint, double> at(double distance) const {
    const auto upper = std::upper_bound(along_.begin(), along_.end(), distance);
    std::size_t i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(upper - along_.begin(), 1));
    i = std::min(i, points_.size() - 1);
    const PixelPoint a = points_[i - 1], b = points_[i];
    const double edge = along_[i] - along_[i - 1];
    const double t = edge > 0.0 ? std::clamp((distance - along_[i - 1]) / edge, 0.0, 1.0) : 0.0;
    return {{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}, std::atan2(b.y - a.y, b.x - a.x)};
  }

 private:
  Road points_;
  std::vector<double> along_;
};

// The UTF-8 characters of a name, each a string of its own (glyphs are set one by one).
std::vector<std::string> characters(const std::string& text) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < text.size();) {
    std::size_t n = 1;
    const auto lead = static_cast<unsigned char>(text[i]);
    if (lead >= 0xf0) {
      n = 4;
    } else if (lead >= 0xe0) {
      n = 3;
    } else if (lead >= 0xc0) {
      n = 2;
    }
    out.push_back(text.substr(i, n));
    i += n;
  }
  return out;
}

struct Glyph {
  std::string text;
  double advance_px = 0.0;
  PixelPoint centre;
  double angle_rad = 0.0;
};

// The room names take: discs around glyphs already set, in a grid of one font size.
class Occupied {
 public:
  explicit Occupied(double radius_px) : radius_(radius_px), cell_(2.0 * radius_px) {}
  bool free(const PixelPoint& p) const {
    const long cx = cell(p.x), cy = cell(p.y);
    for (long dx = -1; dx <= 1; ++dx) {
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find({cx + dx, cy + dy});
        if (it == cells_.end()) continue;
        for (const PixelPoint& q : it->second) {
          if (std::hypot(p.x - q.x, p.y - q.y) < 2.0 * radius_) return false;
        }
      }
    }
    return true;
  }
  void add(const PixelPoint& p) { cells_[{cell(p.x), cell(p.y)}].push_back(p); }

 private:
  long cell(double v) const { return static_cast<long>(std::floor(v / cell_)); }
  double radius_, cell_;
  std::map<std::pair<long, long>, std::vector<PixelPoint>> cells_;
};

double wrap_rad(double a) {
  return std::remainder(a, 2.0 * M_PI);
}

// The glyphs of the name centred `middle` px along the path, upright; empty when the road turns
// too much under them or they leave the map.
std::vector<Glyph> lay_out(const Path& path, double middle, std::vector<Glyph> glyphs,
                           double text_px, const NameLayout& layout) {
  const double start = middle - text_px / 2.0;
  double along = start;
  for (Glyph& g : glyphs) {
    std::tie(g.centre, g.angle_rad) = path.at(along + g.advance_px / 2.0);
    along += g.advance_px;
  }
  // Upright: read left to right, so a road drawn westwards is read from its other end.
  const double mid_angle = path.at(middle).second;
  if (std::cos(mid_angle) < 0.0) {
    along = start;
    for (Glyph& g : glyphs) {
      std::tie(g.centre, g.angle_rad) =
          path.at(start + text_px - (along - start) - g.advance_px / 2.0);
      g.angle_rad = wrap_rad(g.angle_rad + M_PI);
      along += g.advance_px;
    }
  }
  for (std::size_t i = 0; i < glyphs.size(); ++i) {
    const Glyph& g = glyphs[i];
    if (std::abs(wrap_rad(g.angle_rad - glyphs.front().angle_rad)) > layout.max_turn_rad) return {};
    const double margin = layout.font_px;
    if (g.centre.x < margin || g.centre.y < margin || g.centre.x > layout.width_px - margin ||
        g.centre.y > layout.height_px - margin)
      return {};
  }
  return glyphs;
}

void set_glyphs(cairo_t* cr, const std::vector<Glyph>& glyphs, const NameLayout& layout) {
  cairo_new_path(cr);
  for (const Glyph& g : glyphs) {
    cairo_save(cr);
    cairo_translate(cr, g.centre.x, g.centre.y);
    cairo_rotate(cr, g.angle_rad);
    cairo_move_to(cr, -g.advance_px / 2.0, 0.35 * layout.font_px);  // baseline under the centre
    cairo_text_path(cr, g.text.c_str());
    cairo_restore(cr);
  }
  // A white halo keeps the name readable over lines of every colour.
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_set_line_width(cr, std::max(2.0, 0.25 * layout.font_px));
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_stroke_preserve(cr);
  cairo_set_source_rgb(cr, 0.13, 0.13, 0.13);
  cairo_fill(cr);
}

}  // namespace

std::size_t draw_street_names(cairo_t* cr, const std::vector<SegmentLayer>& segments,
                              const std::function<PixelPoint(const schema::PlanePoint&)>& to_px,
                              const NameLayout& layout) {
  std::map<std::string, std::vector<const SegmentLayer*>> by_name;
  for (const SegmentLayer& s : segments) {
    if (!s.assessment.road.name.empty() && s.line.size() >= 2)
      by_name[s.assessment.road.name].push_back(&s);
  }
  struct Candidate {
    std::string name;
    Road road;
    double length_px;
  };
  std::vector<Candidate> roads;
  for (const auto& [name, named] : by_name) {
    for (Road& road : roads_of(named, to_px)) {
      const double length = Path(road).length();
      roads.push_back({name, std::move(road), length});
    }
  }
  // The longest roads choose first: they carry their names best.
  std::stable_sort(roads.begin(), roads.end(), [](const Candidate& a, const Candidate& b) {
    return a.length_px > b.length_px;
  });

  cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, layout.font_px);
  Occupied occupied(0.55 * layout.font_px);
  // Where each name stands already: a dual carriageway or a second road of the same name close
  // by does not repeat it.
  std::map<std::string, std::vector<PixelPoint>> placed_by_name;
  std::size_t drawn = 0;
  for (const Candidate& road : roads) {
    std::vector<Glyph> glyphs;
    double text_px = 0.0;
    for (std::string& c : characters(road.name)) {
      cairo_text_extents_t e;
      cairo_text_extents(cr, c.c_str(), &e);
      text_px += e.x_advance;
      glyphs.push_back({std::move(c), e.x_advance, {}, 0.0});
    }
    const Path path(road.road);
    const double room = path.length() - text_px - 2.0 * layout.font_px;
    if (room < 0.0) continue;
    // Positions from the middle outwards; a long road may carry its name more than once.
    // (repeats of a name keep `spacing` apart)
    const double step = std::max(layout.font_px, text_px / 4.0);
    const double spacing = std::max(5.0 * text_px, 25.0 * layout.font_px);
    std::vector<double> middles;
    for (double offset = 0.0; offset <= room / 2.0; offset += step) {
      middles.push_back(path.length() / 2.0 + offset);
      if (offset > 0.0) middles.push_back(path.length() / 2.0 - offset);
    }
    std::vector<PixelPoint>& placed = placed_by_name[road.name];
    for (double middle : middles) {
      const PixelPoint centre = path.at(middle).first;
      if (std::any_of(placed.begin(), placed.end(), [&](const PixelPoint& p) {
            return std::hypot(p.x - centre.x, p.y - centre.y) < spacing;
          }))
        continue;
      const std::vector<Glyph> laid = lay_out(path, middle, glyphs, text_px, layout);
      if (laid.empty() || !std::all_of(laid.begin(), laid.end(),
                                       [&](const Glyph& g) { return occupied.free(g.centre); }))
        continue;
      for (const Glyph& g : laid) occupied.add(g.centre);
      set_glyphs(cr, laid, layout);
      placed.push_back(centre);
      ++drawn;
    }
  }
  return drawn;
}

}  // namespace roadcross::viz
