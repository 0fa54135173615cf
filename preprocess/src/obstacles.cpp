// Obstacles to the line of sight from OSM: building footprints and walls/fences, as edges with
// an opaque band of heights. Read in two passes of their own (ways, then only the nodes those
// ways use), so memory follows the obstacles and not the file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <osmium/handler.hpp>
#include <osmium/io/any_input.hpp>
#include <osmium/visitor.hpp>

#include "roadcross/preprocess/errors.hpp"
#include "roadcross/preprocess/progress.hpp"
#include "roadcross/preprocess/sight.hpp"

namespace roadcross::preprocess {

double parse_height_m(std::string_view text) noexcept {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  double value = NAN;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || !std::isfinite(value) || value < 0.0) return NAN;
  std::string_view unit(end, static_cast<std::size_t>(text.data() + text.size() - end));
  while (!unit.empty() && unit.front() == ' ') unit.remove_prefix(1);
  while (!unit.empty() && unit.back() == ' ') unit.remove_suffix(1);
  if (unit.empty() || unit == "m") return value;
  if (unit == "ft" || unit == "'") return value * 0.3048;
  return NAN;
}

namespace {

struct ObstacleWay {
  std::vector<std::int64_t> refs;
  float bottom_m = 0.0f, top_m = 0.0f;
};

/// A height from `height_key`, else `levels_key` times the level height; NaN when neither.
double tagged_height_m(const osmium::TagList& tags, const char* height_key, const char* levels_key,
                       double level_height_m) {
  if (const char* h = tags[height_key]) {
    const double m = parse_height_m(h);
    if (!std::isnan(m)) return m;
  }
  if (levels_key) {
    if (const char* levels = tags[levels_key]) {
      const double n = parse_height_m(levels);  // a plain number
      if (!std::isnan(n)) return n * level_height_m;
    }
  }
  return NAN;
}

class ObstacleWayCollector : public osmium::handler::Handler {
 public:
  ObstacleWayCollector(std::vector<ObstacleWay>& ways, ObstacleReport& report,
                       const SightParameters& p)
      : ways_(ways), report_(report), p_(p) {}

  void way(const osmium::Way& way) {
    const osmium::TagList& tags = way.tags();
    const char* building = tags["building"];
    const char* barrier = tags["barrier"];
    ObstacleWay kept;
    double top_m = NAN, default_m = 0.0;
    if (building && std::strcmp(building, "no") != 0 && std::strcmp(building, "roof") != 0) {
      // A roof (fuel station, car port) is open at eye level; so is a passage under a
      // building on pillars, below its min_height.
      top_m = tagged_height_m(tags, "height", "building:levels", p_.level_height_m);
      const double bottom_m =
          tagged_height_m(tags, "min_height", "building:min_level", p_.level_height_m);
      kept.bottom_m = std::isnan(bottom_m) ? 0.0f : static_cast<float>(bottom_m);
      default_m = p_.building_height_m;
      ++report_.buildings;
    } else if (barrier && std::strcmp(barrier, "wall") == 0) {
      top_m = tagged_height_m(tags, "height", nullptr, 0.0);
      default_m = p_.wall_height_m;
      ++report_.walls;
    } else if (barrier && std::strcmp(barrier, "fence") == 0) {
      top_m = tagged_height_m(tags, "height", nullptr, 0.0);
      default_m = p_.fence_height_m;
      ++report_.fences;
    } else {
      return;
    }
    if (std::isnan(top_m)) top_m = default_m, ++report_.default_height;
    kept.top_m = static_cast<float>(top_m);
    for (const osmium::NodeRef& ref : way.nodes()) kept.refs.push_back(ref.ref());
    if (kept.refs.size() >= 2 && kept.top_m > kept.bottom_m) ways_.push_back(std::move(kept));
  }

  void relation(const osmium::Relation& relation) {
    const char* type = relation.tags()["type"];
    if (relation.tags()["building"] && type && std::strcmp(type, "multipolygon") == 0) {
      ++report_.relations_skipped;
    }
  }

 private:
  std::vector<ObstacleWay>& ways_;
  ObstacleReport& report_;
  const SightParameters& p_;
};

struct Located {
  std::int64_t id;
  PlanePoint utm;
};

class NodeCollector : public osmium::handler::Handler {
 public:
  /// Keeps the wanted nodes inside [min, max] (UTM).
  NodeCollector(const std::vector<std::int64_t>& wanted, const geo::UtmZone& zone,
                const PlanePoint& min, const PlanePoint& max, std::vector<Located>& out)
      : wanted_(wanted), zone_(zone), min_(min), max_(max), out_(out) {}
  void node(const osmium::Node& node) {
    if (!std::binary_search(wanted_.begin(), wanted_.end(), node.id())) return;
    const osmium::Location l = node.location();
    if (!l.valid()) return;
    const geo::UtmPoint p = geo::wgs84_to_utm(l.lat(), l.lon(), zone_);
    if (p.easting_m < min_.x || p.easting_m > max_.x || p.northing_m < min_.y ||
        p.northing_m > max_.y) {
      return;
    }
    out_.push_back({node.id(), {p.easting_m, p.northing_m}});
  }

 private:
  const std::vector<std::int64_t>& wanted_;
  const geo::UtmZone& zone_;
  PlanePoint min_, max_;
  std::vector<Located>& out_;
};

template <typename Handler>
void read_pass(const std::string& path, osmium::osm_entity_bits::type entities, Handler& handler,
               Progress& progress) {
  osmium::io::Reader reader{osmium::io::File{path}, entities};
  const std::uint64_t size = reader.file_size();
  while (osmium::memory::Buffer buffer = reader.read()) {
    osmium::apply(buffer, handler);
    progress.update(reader.offset(), size);
  }
  reader.close();
}

}  // namespace

Obstacles read_obstacles(const std::string& osm_path, const geo::UtmZone& zone,
                         const PlanePoint& min, const PlanePoint& max, double reach_m,
                         const SightParameters& p, Progress& progress) {
  Obstacles out;
  std::vector<ObstacleWay> ways;
  std::vector<Located> nodes;
  try {
    progress.start_stage("reading buildings and walls", "MB");
    ObstacleWayCollector collector(ways, out.report, p);
    read_pass(osm_path, osmium::osm_entity_bits::way | osmium::osm_entity_bits::relation, collector,
              progress);
    std::vector<std::int64_t> wanted;
    for (const ObstacleWay& w : ways) wanted.insert(wanted.end(), w.refs.begin(), w.refs.end());
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    // Nodes far from the roads are not kept (a country's buildings would not fit); the margin
    // keeps both ends of long edges (a wall, a large hall) that reach the sight lines' area.
    constexpr double kLongEdgeM = 1000.0;
    const double node_reach_m = reach_m + kLongEdgeM;
    NodeCollector node_collector(wanted, zone, {min.x - node_reach_m, min.y - node_reach_m},
                                 {max.x + node_reach_m, max.y + node_reach_m}, nodes);
    read_pass(osm_path, osmium::osm_entity_bits::node, node_collector, progress);
  } catch (const std::exception& e) {
    throw InputError(osm_path, std::string("not readable as OSM data: ") + e.what());
  }
  std::sort(nodes.begin(), nodes.end(),
            [](const Located& a, const Located& b) { return a.id < b.id; });
  const auto find = [&](std::int64_t id) -> const PlanePoint* {
    const auto it = std::lower_bound(nodes.begin(), nodes.end(), id,
                                     [](const Located& n, std::int64_t v) { return n.id < v; });
    return it != nodes.end() && it->id == id ? &it->utm : nullptr;
  };
  // Only edges a sight line can meet: within reach of the roads' box.
  const auto near = [&](const PlanePoint& a, const PlanePoint& b) {
    return std::max(a.x, b.x) >= min.x - reach_m && std::min(a.x, b.x) <= max.x + reach_m &&
           std::max(a.y, b.y) >= min.y - reach_m && std::min(a.y, b.y) <= max.y + reach_m;
  };
  for (const ObstacleWay& w : ways) {
    for (std::size_t i = 1; i < w.refs.size(); ++i) {
      const PlanePoint* a = find(w.refs[i - 1]);
      const PlanePoint* b = find(w.refs[i]);
      if (a && b && near(*a, *b)) out.edges.push_back({*a, *b, w.bottom_m, w.top_m});
    }
  }
  out.report.edges = out.edges.size();
  progress.finish_stage(std::to_string(out.report.buildings) + " buildings, " +
                        std::to_string(out.report.walls) + " walls, " +
                        std::to_string(out.report.fences) + " fences, " +
                        std::to_string(out.report.edges) + " edges");
  return out;
}

}  // namespace roadcross::preprocess
