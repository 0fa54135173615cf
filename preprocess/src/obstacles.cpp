// Obstacles to the line of sight from OSM: building footprints and walls/fences, as edges with
// an opaque band of heights. Read in the road network's two passes (ways, then only the nodes
// those ways use), so memory follows the obstacles and not the file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <osmium/osm/node.hpp>
#include <osmium/osm/relation.hpp>
#include <osmium/osm/way.hpp>
#include <stdexcept>
#include <thread>

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

}  // namespace

void ObstacleReader::way(const osmium::Way& way) {
  const osmium::TagList& tags = way.tags();
  const char* building = tags["building"];
  const char* barrier = tags["barrier"];
  double top_m = NAN, bottom_m = 0.0, default_m = 0.0;
  if (building && std::strcmp(building, "no") != 0 && std::strcmp(building, "roof") != 0) {
    // A roof (fuel station, car port) is open at eye level; so is a passage under a
    // building on pillars, below its min_height.
    top_m = tagged_height_m(tags, "height", "building:levels", p_.level_height_m);
    bottom_m = tagged_height_m(tags, "min_height", "building:min_level", p_.level_height_m);
    if (std::isnan(bottom_m)) bottom_m = 0.0;
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
  const auto bottom = static_cast<float>(bottom_m), top = static_cast<float>(top_m);
  if (way.nodes().size() < 2 || !(top > bottom)) return;
  ways_.push_back({refs_.size(), bottom, top});
  for (const osmium::NodeRef& ref : way.nodes()) refs_.push_back(ref.ref());
}

void ObstacleReader::relation(const osmium::Relation& relation) {
  const char* type = relation.tags()["type"];
  if (relation.tags()["building"] && type && std::strcmp(type, "multipolygon") == 0) {
    ++report_.relations_skipped;
  }
}

void ObstacleReader::ways_done() {
  node_ids_ = refs_;
  std::sort(node_ids_.begin(), node_ids_.end());
  node_ids_.erase(std::unique(node_ids_.begin(), node_ids_.end()), node_ids_.end());
  node_ids_.shrink_to_fit();
  // The references become positions in node_ids_ (half the size), read in place.
  ref_nodes_.resize(refs_.size());
  // A building's nodes usually have consecutive ids: try the one after the previous first.
  std::size_t at = 0;
  for (std::size_t i = 0; i < refs_.size(); ++i) {
    if (at + 1 < node_ids_.size() && node_ids_[at + 1] == refs_[i]) {
      ++at;
    } else if (node_ids_[at] != refs_[i]) {
      at = static_cast<std::size_t>(std::lower_bound(node_ids_.begin(), node_ids_.end(), refs_[i]) -
                                    node_ids_.begin());
    }
    ref_nodes_[i] = static_cast<std::uint32_t>(at);
  }
  std::vector<std::int64_t>().swap(refs_);
  nodes_.assign(node_ids_.size(), PlanePoint{NAN, NAN});
}

void ObstacleReader::nodes_done() {
  // The ids only served the lookup in node(): the segment table and the edges come next.
  std::vector<std::int64_t>().swap(node_ids_);
}

void ObstacleReader::node(const osmium::Node& node) {
  const auto it = std::lower_bound(node_ids_.begin(), node_ids_.end(), node.id());
  if (it == node_ids_.end() || *it != node.id()) return;
  const osmium::Location l = node.location();
  if (!l.valid()) return;
  nodes_[static_cast<std::size_t>(it - node_ids_.begin())] = {l.lon(), l.lat()};
}

Obstacles ObstacleReader::take_edges(const geo::UtmZone& zone, const PlanePoint& min,
                                     const PlanePoint& max, double reach_m) {
  Obstacles out;
  out.report = report_;
  // Nodes far from the roads are not kept (a country's buildings would not fit); the margin
  // keeps both ends of long edges (a wall, a large hall) that reach the sight lines' area.
  constexpr double kLongEdgeM = 1000.0;
  const double node_reach_m = reach_m + kLongEdgeM;
  // (lon, lat) -> UTM in place, NaN when missing or far; on every core (the projection is most
  // of this stage's time).
  const auto project = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      PlanePoint& q = nodes_[i];
      if (std::isnan(q.x)) continue;
      bool kept = false;
      geo::UtmPoint u;
      try {
        u = geo::wgs84_to_utm(q.y, q.x, zone);
        kept = u.easting_m >= min.x - node_reach_m && u.easting_m <= max.x + node_reach_m &&
               u.northing_m >= min.y - node_reach_m && u.northing_m <= max.y + node_reach_m;
      } catch (const std::invalid_argument&) {
        // Too far from the roads' UTM zone to project: far from every road as well.
      }
      q = kept ? PlanePoint{u.easting_m, u.northing_m} : PlanePoint{NAN, NAN};
    }
  };
  const std::size_t threads = std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 16);
  std::vector<std::thread> pool;
  const std::size_t chunk = (nodes_.size() + threads - 1) / threads;
  for (std::size_t t = 1; t < threads; ++t) {
    pool.emplace_back(project, std::min(nodes_.size(), t * chunk),
                      std::min(nodes_.size(), (t + 1) * chunk));
  }
  project(0, std::min(nodes_.size(), chunk));
  for (std::thread& t : pool) t.join();
  // Only edges a sight line can meet: within reach of the roads' box.
  const auto near = [&](const PlanePoint& a, const PlanePoint& b) {
    return std::max(a.x, b.x) >= min.x - reach_m && std::min(a.x, b.x) <= max.x + reach_m &&
           std::max(a.y, b.y) >= min.y - reach_m && std::min(a.y, b.y) <= max.y + reach_m;
  };
  out.edges.reserve(ref_nodes_.size() - ways_.size());  // at most: no doubling at the peak
  for (std::size_t w = 0; w < ways_.size(); ++w) {
    const std::size_t end = w + 1 < ways_.size() ? ways_[w + 1].first_ref : ref_nodes_.size();
    for (std::size_t i = ways_[w].first_ref + 1; i < end; ++i) {
      const PlanePoint& a = nodes_[ref_nodes_[i - 1]];
      const PlanePoint& b = nodes_[ref_nodes_[i]];
      if (!std::isnan(a.x) && !std::isnan(b.x) && near(a, b)) {
        out.edges.push_back({a, b, ways_[w].bottom_m, ways_[w].top_m});
      }
    }
  }
  out.report.edges = out.edges.size();
  // What was read is no longer needed: the edges are what the sight stage uses.
  std::vector<Way>().swap(ways_);
  std::vector<std::uint32_t>().swap(ref_nodes_);
  std::vector<std::int64_t>().swap(node_ids_);
  std::vector<PlanePoint>().swap(nodes_);
  return out;
}

}  // namespace roadcross::preprocess
