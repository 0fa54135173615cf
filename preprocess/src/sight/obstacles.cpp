// Obstacles to the line of sight from OSM: building footprints and walls/fences, as edges with
// an opaque band of heights. Read in the road network's two passes (ways, then only the nodes
// those ways use), so memory follows the obstacles and not the file.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <future>
#include <limits>
#include <osmium/osm/node.hpp>
#include <osmium/osm/relation.hpp>
#include <osmium/osm/way.hpp>
#include <stdexcept>
#include <thread>
#include <utility>

#include "roadcross/preprocess/common/huge_pages.hpp"
#include "roadcross/preprocess/common/id_buckets.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/common/utm_grid.hpp"
#include "roadcross/preprocess/sight/sight.hpp"

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

// Slots that hold no vertex: until take_edges() a slot holds a Location's (x, y) (|x| <= 180e7),
// or (kReference, the slot of the node's first reference), or kNoVertex twice (not in the file);
// take_edges() projects the Locations to fixed-point vertices (x >= 0) or kNoVertex (far).
constexpr std::int32_t kReference = std::numeric_limits<std::int32_t>::min();
constexpr std::int32_t kNoVertex = std::numeric_limits<std::int32_t>::min() + 1;

/// A height from the height tag's value, else the levels' (nullptr: none) times the level
/// height; NaN when neither reads.
double tagged_height_m(const char* height, const char* levels, double level_height_m) {
  if (height) {
    const double m = parse_height_m(height);
    if (!std::isnan(m)) return m;
  }
  if (levels) {
    const double n = parse_height_m(levels);  // a plain number
    if (!std::isnan(n)) return n * level_height_m;
  }
  return NAN;
}

}  // namespace

ObstacleTags read_obstacle_tags(const osmium::TagList& tags) noexcept {
  // Each TagList::operator[] walks the whole list with a strcmp a tag; a way was asked for up to
  // six keys (building, barrier, then the heights), on every way of the file.
  ObstacleTags out;
  const auto first = [](const char*& slot, const osmium::Tag& tag) {
    if (!slot) slot = tag.value();
  };
  for (const osmium::Tag& tag : tags) {
    const char* key = tag.key();
    switch (key[0]) {
      case 'b':
        if (std::strcmp(key, "building") == 0) {
          first(out.building, tag);
        } else if (std::strcmp(key, "barrier") == 0) {
          first(out.barrier, tag);
        } else if (std::strcmp(key, "building:levels") == 0) {
          first(out.building_levels, tag);
        } else if (std::strcmp(key, "building:min_level") == 0) {
          first(out.building_min_level, tag);
        }
        break;
      case 'h':
        if (std::strcmp(key, "height") == 0) first(out.height, tag);
        break;
      case 'm':
        if (std::strcmp(key, "min_height") == 0) first(out.min_height, tag);
        break;
      default:
        break;
    }
  }
  return out;
}

void ObstacleReader::way(const osmium::Way& way) {
  const ObstacleTags tags = read_obstacle_tags(way.tags());
  const char* building = tags.building;
  const char* barrier = tags.barrier;
  double top_m = NAN, bottom_m = 0.0, default_m = 0.0;
  if (building && std::strcmp(building, "no") != 0 && std::strcmp(building, "roof") != 0) {
    // A roof (fuel station, car port) is open at eye level; so is a passage under a
    // building on pillars, below its min_height.
    top_m = tagged_height_m(tags.height, tags.building_levels, p_.level_height_m);
    bottom_m = tagged_height_m(tags.min_height, tags.building_min_level, p_.level_height_m);
    if (std::isnan(bottom_m)) bottom_m = 0.0;
    default_m = p_.building_height_m;
    ++report_.buildings;
  } else if (barrier && std::strcmp(barrier, "wall") == 0) {
    top_m = tagged_height_m(tags.height, nullptr, 0.0);
    default_m = p_.wall_height_m;
    ++report_.walls;
  } else if (barrier && std::strcmp(barrier, "fence") == 0) {
    top_m = tagged_height_m(tags.height, nullptr, 0.0);
    default_m = p_.fence_height_m;
    ++report_.fences;
  } else {
    return;
  }
  if (std::isnan(top_m)) top_m = default_m, ++report_.default_height;
  const auto bottom = static_cast<float>(bottom_m), top = static_cast<float>(top_m);
  if (way.nodes().size() < 2 || !(top > bottom)) return;
  // Slot numbers (a header per way, one per reference, and the cuts of long ways) must fit the
  // edge ids.
  const std::size_t k = way.nodes().size();
  if (cut_slots_ + refs_.size() + ways_.size() + 1 + k + 2 * k >
      std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("sight: more than 2^32 - 1 obstacle node references");
  }
  cut_slots_ += ObstacleEdges::slots_for_chain(k - 1) - (k + 1);
  ways_.push_back({static_cast<std::uint32_t>(refs_.size() + ways_.size()), bottom, top});
  // Grown by doubling as push_back would, on huge pages (millions of references).
  if (refs_.capacity() - refs_.size() < k) {
    reserve_on_huge_pages(refs_, std::max(2 * refs_.capacity(), refs_.size() + k));
  }
  for (const osmium::NodeRef& ref : way.nodes()) refs_.push_back(ref.ref());
}

void ObstacleReader::relation(const osmium::Relation& relation) {
  const char* type = relation.tags()["type"];
  if (relation.tags()["building"] && type && std::strcmp(type, "multipolygon") == 0) {
    ++report_.relations_skipped;
  }
}

void ObstacleReader::ways_done() {
  // The ways' slots go after room for the cuts of their long chains, so that take_edges, writing
  // runs from slot 0, never overtakes what it has not read yet.
  for (Way& way : ways_) way.first_slot += static_cast<std::uint32_t>(cut_slots_);
  const std::size_t slots = cut_slots_ + refs_.size() + ways_.size();
  // refs_[r] of way w is at slot r + w + 1 + cut_slots_ (its header and those of the ways
  // before, after the cuts' room): the items are made in refs_' order, so a running way index
  // gives each its slot. Way w's first reference is first_slot - cut_slots_ - w.
  std::size_t w = 0;
  const auto make_item = [&](std::size_t r) {
    while (w + 1 < ways_.size() && r + w + 1 + cut_slots_ >= ways_[w + 1].first_slot) ++w;
    const auto id = static_cast<std::uint64_t>(refs_[r]);
    return NodeSlot{static_cast<std::uint32_t>(id), static_cast<std::uint32_t>(id >> 32),
                    static_cast<std::uint32_t>(r + w + 1 + cut_slots_)};
  };
  // The slots' array is allocated and filled beside the sort (both are first writes of
  // hundreds of MiB at country scale, and the other core is otherwise idle here: the road
  // tables' sorts end first). Both tables at once stay far below the build's later peak.
  std::future<void> slots_filled = std::async(std::launch::async, [this, slots] {
    resize_on_huge_pages(slots_, slots);
    std::fill(slots_.begin(), slots_.end(), FixedSlot{kNoVertex, kNoVertex});
  });
  // By id alone: the slots of one node all get the same location, in any order.
  buckets_ = sort_into_id_buckets(
      refs_, make_item, [](const NodeSlot& x) { return x.id(); }, node_slots_);
  std::vector<std::int64_t>().swap(refs_);
  slots_filled.get();
}

void ObstacleReader::nodes_done() {
  // The ids only served the lookup in node(): the segment table and the edges come next.
  decltype(node_slots_)().swap(node_slots_);
  buckets_ = IdBuckets();
}

void ObstacleReader::node(std::int64_t id, osmium::Location location) {
  const auto [first_item, end_item] = buckets_.range_of(id);
  if (first_item == end_item) return;
  const auto end = node_slots_.begin() + static_cast<std::ptrdiff_t>(end_item);
  auto it =
      std::lower_bound(node_slots_.begin() + static_cast<std::ptrdiff_t>(first_item), end, id,
                       [](const NodeSlot& x, std::int64_t wanted) { return x.id() < wanted; });
  if (it == end || it->id() != id) return;
  const osmium::Location l = location;
  if (!l.valid()) return;
  // The first reference holds the location, the others point to it (projected once).
  const std::uint32_t first = it->slot;
  slots_[first] = {l.x(), l.y()};
  for (++it; it != end && it->id() == id; ++it) {
    slots_[it->slot] = {kReference, std::bit_cast<std::int32_t>(first)};
  }
}

namespace {

/// The grid of exact projections (UtmGrid) whose cells cover the UTM box [min, max] of `zone`:
/// its sides sampled every eighth of their length in latitude and longitude (a side of
/// constant easting or northing is not one of constant longitude or latitude), with two cells
/// of margin. None when the box cannot be projected back or the grid would be too large.
UtmGrid projection_grid(const geo::UtmZone& zone, const PlanePoint& min, const PlanePoint& max) {
  double lat_lo = 90.0, lat_hi = -90.0, lon_lo = 180.0, lon_hi = -180.0;
  try {
    for (int k = 0; k <= 8; ++k) {
      const double x = min.x + (max.x - min.x) * k / 8.0, y = min.y + (max.y - min.y) * k / 8.0;
      for (const PlanePoint& p : {PlanePoint{x, min.y}, PlanePoint{x, max.y}, PlanePoint{min.x, y},
                                  PlanePoint{max.x, y}}) {
        const geo::LatLon l = geo::utm_to_wgs84(p.x, p.y, zone);
        lat_lo = std::min(lat_lo, l.lat_deg), lat_hi = std::max(lat_hi, l.lat_deg);
        lon_lo = std::min(lon_lo, l.lon_deg), lon_hi = std::max(lon_hi, l.lon_deg);
      }
    }
  } catch (const std::exception&) {
    return UtmGrid();
  }
  if (!(lat_lo <= lat_hi && lon_lo <= lon_hi)) return UtmGrid();
  constexpr double kMarginDeg = 2.0 * UtmGrid::kStepE7 / 1e7;
  const auto e7 = [](double deg, double limit) {
    return static_cast<std::int32_t>(std::clamp(deg, -limit, limit) * 1e7);
  };
  return UtmGrid(zone, e7(lon_lo - kMarginDeg, 180.0), e7(lat_lo - kMarginDeg, 90.0),
                 e7(lon_hi + kMarginDeg, 180.0), e7(lat_hi + kMarginDeg, 90.0));
}

}  // namespace

Obstacles ObstacleReader::take_edges(const geo::UtmZone& zone, const PlanePoint& min,
                                     const PlanePoint& max, double reach_m) {
  Obstacles out;
  out.report = report_;
  // Nodes far from the roads are not kept (a country's buildings would not fit); the margin
  // keeps both ends of long edges (a wall, a large hall) that reach the sight lines' area.
  constexpr double kLongEdgeM = 1000.0;
  const double node_reach_m = reach_m + kLongEdgeM;
  // Every kept node is inside this box: the frame of the fixed-point vertices (throws, naming
  // the extent, when it is too wide for them). An empty box (no road) keeps no node.
  const bool any_road = min.x <= max.x && min.y <= max.y;
  const VertexFrame frame =
      any_road ? VertexFrame::covering({min.x - node_reach_m, min.y - node_reach_m},
                                       {max.x + node_reach_m, max.y + node_reach_m})
               : VertexFrame();
  // Location -> UTM -> fixed point in place, kNoVertex when missing or far; on every core.
  // (lon, lat) as the node pass read them: the same doubles as Location::lon() and lat() there.
  // A node's other references (kReference, its first slot) are copied after.
  // Most nodes take the interpolated projection: where it gives the exact one's answer for
  // certain (inside or outside the box, the fixed point) whatever its error.
  const UtmGrid grid = any_road
                           ? projection_grid(zone, {min.x - node_reach_m, min.y - node_reach_m},
                                             {max.x + node_reach_m, max.y + node_reach_m})
                           : UtmGrid();
  const auto by_grid = [&](FixedSlot& q) {
    double e = 0.0, n = 0.0;
    if (!grid.project(q.x, q.y, e, n)) return false;
    constexpr double kError = UtmGrid::kErrorBoundM;
    const double lo_x = min.x - node_reach_m, hi_x = max.x + node_reach_m;
    const double lo_y = min.y - node_reach_m, hi_y = max.y + node_reach_m;
    if (e < lo_x - kError || e > hi_x + kError || n < lo_y - kError || n > hi_y + kError) {
      q = FixedSlot{kNoVertex, kNoVertex};
      return true;
    }
    if (!(e > lo_x + kError && e < hi_x - kError && n > lo_y + kError && n < hi_y - kError)) {
      return false;
    }
    return frame.encode_certain({e, n}, kError, q);
  };
  const auto project_one = [&](FixedSlot& q) {
    if (q.x == kReference || q.x == kNoVertex) return;
    if (by_grid(q)) return;
    const osmium::Location l(q.x, q.y);
    bool kept = false;
    geo::UtmPoint u;
    try {
      u = geo::wgs84_to_utm(l.lat(), l.lon(), zone);
      kept = any_road && u.easting_m >= min.x - node_reach_m &&
             u.easting_m <= max.x + node_reach_m && u.northing_m >= min.y - node_reach_m &&
             u.northing_m <= max.y + node_reach_m;
    } catch (const std::invalid_argument&) {
      // Too far from the roads' UTM zone to project: far from every road as well.
    }
    q = kept ? frame.encode({u.easting_m, u.northing_m}) : FixedSlot{kNoVertex, kNoVertex};
  };
  const auto project = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) project_one(slots_[i]);
  };
  const auto copy_references = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const FixedSlot q = slots_[i];
      if (q.x == kReference) slots_[i] = slots_[std::bit_cast<std::uint32_t>(q.y)];
    }
  };
  // Headers are kNoVertex until the compaction writes them: both passes leave them.
  const std::size_t parts = core_count();
  const std::size_t part_size = (slots_.size() + parts - 1) / parts;
  for (const auto& pass : {std::function<void(std::size_t, std::size_t)>(project),
                           std::function<void(std::size_t, std::size_t)>(copy_references)}) {
    parallel_for<NoState>(parts, [&](std::size_t part, NoState&) {
      pass(std::min(slots_.size(), part * part_size),
           std::min(slots_.size(), (part + 1) * part_size));
    });
  }
  // Only edges a sight line can meet: within reach of the roads' box.
  const auto near = [&](FixedSlot p, FixedSlot q) {
    const PlanePoint a = frame.decode(p), b = frame.decode(q);
    return std::max(a.x, b.x) >= min.x - reach_m && std::min(a.x, b.x) <= max.x + reach_m &&
           std::max(a.y, b.y) >= min.y - reach_m && std::min(a.y, b.y) <= max.y + reach_m;
  };
  // Each way's maximal chains of kept edges become runs, written in place from slot 0 over the
  // slots read: a way's runs take no more slots than it had plus its cuts' room (before the
  // first way), unless a far edge between two kept ones splits a chain: then, if they would
  // overtake the next way, they go to `overflow`, appended at the end (which may then need a
  // larger array: only when nothing else was dropped).
  std::vector<FixedSlot> way_vertices;
  ObstacleEdges::Slots overflow;
  std::vector<std::pair<std::size_t, std::size_t>> chains;  // [first, last] vertex, all kept
  FixedSlot* const base = slots_.data();
  FixedSlot* write = base;
  for (std::size_t w = 0; w < ways_.size(); ++w) {
    const FixedSlot* first = base + ways_[w].first_slot + 1;
    const FixedSlot* end = base + end_slot(w);
    way_vertices.assign(first, end);
    const std::size_t n = way_vertices.size();
    chains.clear();
    std::size_t needed = 0;
    for (std::size_t i = 1, chain_begin = 0; i <= n; ++i) {
      const bool kept = i < n && way_vertices[i - 1].x >= 0 && way_vertices[i].x >= 0 &&
                        near(way_vertices[i - 1], way_vertices[i]);
      if (!kept) {
        if (i - 1 > chain_begin) {
          chains.emplace_back(chain_begin, i - 1);
          needed += ObstacleEdges::slots_for_chain(i - 1 - chain_begin);
          out.report.edges += i - 1 - chain_begin;
        }
        chain_begin = i;
      }
    }
    const bool in_place = write + needed <= end;
    if (!in_place) overflow.resize(overflow.size() + needed);
    FixedSlot* to = in_place ? write : overflow.data() + overflow.size() - needed;
    for (const auto& [b, l] : chains) {
      to = ObstacleEdges::write_chain(to, ways_[w].bottom_m, ways_[w].top_m,
                                      way_vertices.data() + b, way_vertices.data() + l);
    }
    if (in_place) write = to;
  }
  slots_.resize(static_cast<std::size_t>(write - base));
  slots_.insert(slots_.end(), overflow.begin(), overflow.end());
  // What was read is no longer needed: the edges are what the sight stage uses. (Not shrunk:
  // that would copy them; what the dropped far ways leave is at most what was read.)
  std::vector<Way>().swap(ways_);
  out.edges = ObstacleEdges::adopt(std::move(slots_), frame);
  slots_ = {};
  return out;
}

}  // namespace roadcross::preprocess
