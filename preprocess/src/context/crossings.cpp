#include "roadcross/preprocess/context/crossings.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/context/kerb_tags.hpp"

namespace roadcross::preprocess {

namespace {

/// Geometric hits closer than this to another point of the same way are the same place.
constexpr double kSamePlaceM = 0.5;
/// Cell size of the grid of road edges used to find footway/road intersections, metres.
constexpr double kGridCellM = 50.0;

bool is_signal_ref(std::string_view ref) {
  return ref == "pelican" || ref == "toucan" || ref == "puffin" || ref == "pegasus";
}

CrossingKind kind_from_tags(const Tags& tags) {
  const std::string_view crossing = tag_value(tags, "crossing");
  const std::string_view ref = tag_value(tags, "crossing_ref");
  const std::string_view markings = tag_value(tags, "crossing:markings");
  const std::string_view signals = tag_value(tags, "crossing:signals");
  CrossingKind kind;
  if (!crossing.empty()) {
    kind.type = crossing;
  } else if (!ref.empty()) {
    kind.type = ref;
  } else if (!markings.empty()) {
    kind.type = markings == "no" ? "unmarked" : "marked";
  } else if (signals == "yes") {
    kind.type = "traffic_signals";
  } else {
    kind.type = "unspecified";
  }
  kind.signals = crossing == "traffic_signals" || signals == "yes" || is_signal_ref(ref);
  kind.designated = crossing != "informal" && crossing != "no";
  return kind;
}

/// Where a node lies on the graph (one entry per piece that has it as a vertex).
struct GraphPlace {
  std::size_t piece = 0;
  std::size_t vertex = 0;
  double offset_m = 0.0;
};

/// Places of the wanted nodes (sorted ids) on the pieces, by node identity.
std::unordered_map<std::int64_t, std::vector<GraphPlace>> place_nodes(
    const RoadGraph& graph, const std::vector<std::int64_t>& wanted_sorted) {
  std::unordered_map<std::int64_t, std::vector<GraphPlace>> places;
  for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
    const RoadPiece& piece = graph.pieces[p];
    double offset_m = 0.0;
    for (std::size_t v = 0; v < piece.node_ids.size(); ++v) {
      if (v > 0) {
        offset_m += std::hypot(piece.points[v].x - piece.points[v - 1].x,
                               piece.points[v].y - piece.points[v - 1].y);
      }
      if (std::binary_search(wanted_sorted.begin(), wanted_sorted.end(), piece.node_ids[v])) {
        places[piece.node_ids[v]].push_back({p, v, offset_m});
      }
    }
  }
  return places;
}

/// Index of the segment of `piece` that contains `offset_m`.
std::int64_t segment_at(const RoadGraph& graph, const RoadPiece& piece, double offset_m) {
  std::size_t index = piece.first_segment;
  for (std::size_t k = 1; k < piece.segment_count; ++k) {
    if (graph.offset_in_piece_m(graph.segments[piece.first_segment + k]) <= offset_m) {
      index = piece.first_segment + k;
    }
  }
  return RoadGraph::id_at(index);
}

/// A crossing at the first place of a node; the segment is the lowest id touching it.
Crossing crossing_at(const RoadGraph& graph, const std::vector<GraphPlace>& places) {
  Crossing c;
  c.segment_id = std::numeric_limits<std::int64_t>::max();
  for (const GraphPlace& place : places) {
    const std::int64_t id = segment_at(graph, graph.pieces[place.piece], place.offset_m);
    if (id < c.segment_id) {
      c.segment_id = id;
      c.piece_index = place.piece;
      c.offset_in_piece_m = place.offset_m;
      c.point = graph.pieces[place.piece].points[place.vertex];
    }
  }
  return c;
}

/// The road edges of the graph in a uniform grid, for intersection tests.
class EdgeGrid {
 public:
  struct Edge {
    std::size_t piece = 0;
    std::size_t edge = 0;  ///< from points[edge] to points[edge + 1]
  };

  /// Only the cells in `wanted` (sorted keys of the cells the lines to test pass near, see
  /// add_cells) are filled: the grid of every road edge would cost ~60 bytes an edge at
  /// country scale, beside the road network at the build's peak memory.
  EdgeGrid(const RoadGraph& graph, const std::vector<std::int64_t>& wanted) {
    for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
      const auto& pts = graph.pieces[p].points;
      for (std::size_t e = 0; e + 1 < pts.size(); ++e) {
        for_cells(pts[e], pts[e + 1], [&](std::int64_t key) {
          if (std::binary_search(wanted.begin(), wanted.end(), key)) {
            cells_[key].push_back({p, e});
          }
        });
      }
    }
  }

  /// Appends the keys of the cells that near(a, b) visits.
  static void add_cells(PlanePoint a, PlanePoint b, std::vector<std::int64_t>& keys) {
    for_cells(a, b, [&](std::int64_t key) { keys.push_back(key); });
  }

  /// Calls `visit` for every road edge in the cells the line a-b passes near (may repeat).
  void near(PlanePoint a, PlanePoint b, const std::function<void(const Edge&)>& visit) const {
    for_cells(a, b, [&](std::int64_t key) {
      const auto it = cells_.find(key);
      if (it == cells_.end()) return;
      for (const Edge& e : it->second) visit(e);
    });
  }

 private:
  template <typename F>
  static void for_cells(PlanePoint a, PlanePoint b, F f) {
    const auto cell = [](double v) {
      return static_cast<std::int64_t>(std::floor(v / kGridCellM));
    };
    for (std::int64_t x = cell(std::min(a.x, b.x)); x <= cell(std::max(a.x, b.x)); ++x) {
      for (std::int64_t y = cell(std::min(a.y, b.y)); y <= cell(std::max(a.y, b.y)); ++y) {
        f(x * 4'000'003 + y);
      }
    }
  }

  std::unordered_map<std::int64_t, std::vector<Edge>> cells_;
};

/// Parameter t along p1-p2 where it crosses q1-q2 (both t and u in [0, 1]), or nullopt.
std::optional<std::pair<double, double>> intersect(PlanePoint p1, PlanePoint p2, PlanePoint q1,
                                                   PlanePoint q2) {
  const double rx = p2.x - p1.x, ry = p2.y - p1.y, sx = q2.x - q1.x, sy = q2.y - q1.y;
  const double denominator = rx * sy - ry * sx;
  if (std::abs(denominator) < 1e-12) return std::nullopt;  // parallel or degenerate
  const double qx = q1.x - p1.x, qy = q1.y - p1.y;
  const double t = (qx * sy - qy * sx) / denominator;
  const double u = (qx * ry - qy * rx) / denominator;
  if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::nullopt;
  return std::make_pair(t, u);
}

double distance(PlanePoint a, PlanePoint b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

/// Tags of a node of a road way or of a crossing way that carries interesting tags, or null.
const Tags* node_tags(const RoadNetwork& network, std::int64_t id) {
  for (const std::vector<TaggedNode>* list :
       {&network.tagged_nodes, &network.crossing_way_tagged_nodes}) {
    const auto it =
        std::lower_bound(list->begin(), list->end(), id,
                         [](const TaggedNode& n, std::int64_t v) { return n.osm_id < v; });
    if (it != list->end() && it->osm_id == id) return &it->tags;
  }
  return nullptr;
}

class CrossingFinder {
 public:
  CrossingFinder(const RoadNetwork& network, const RoadGraph& graph)
      : network_(network), graph_(graph) {
    std::vector<std::int64_t> wanted;
    for (const TaggedNode& node : network.tagged_nodes) {
      if (node_crossing_kind(node.tags)) wanted.push_back(node.osm_id);
    }
    for (const CrossingWay& way : network.crossing_ways) {
      wanted.insert(wanted.end(), way.node_ids.begin(), way.node_ids.end());
    }
    std::sort(wanted.begin(), wanted.end());
    wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
    places_ = place_nodes(graph, wanted);
    way_kerbs_.reserve(network.crossing_ways.size());
    for (std::size_t w = 0; w < network.crossing_ways.size(); ++w) {
      const CrossingWay& way = network.crossing_ways[w];
      KerbFacts facts = kerb_facts(way.tags);
      for (std::int64_t id : way.node_ids) {
        if (const Tags* tags = node_tags(network, id)) merge_kerb_facts(facts, kerb_facts(*tags));
        ways_through_[id].push_back(w);
      }
      way_kerbs_.push_back(std::move(facts));
    }
  }

  std::vector<Crossing> find() {
    std::vector<Crossing> out;
    for (const TaggedNode& node : network_.tagged_nodes) add_node(node, out);
    if (!network_.crossing_ways.empty()) {
      EdgeGrid grid(graph_, cells_along_crossing_ways());
      for (const CrossingWay& way : network_.crossing_ways) add_way(way, grid, out);
    }
    return out;
  }

 private:
  void add_node(const TaggedNode& node, std::vector<Crossing>& out) {
    const std::optional<CrossingKind> kind = node_crossing_kind(node.tags);
    const auto it = places_.find(node.osm_id);
    if (!kind || it == places_.end()) return;  // not a crossing, or not on the road graph
    Crossing c = crossing_at(graph_, it->second);
    c.osm_id = node.osm_id;
    c.osm_type = "node";
    c.kind = *kind;
    c.kerb = kerb_facts(node.tags);
    if (const auto ways = ways_through_.find(node.osm_id); ways != ways_through_.end()) {
      for (std::size_t w : ways->second) merge_kerb_facts(c.kerb, way_kerbs_[w]);
    }
    out.push_back(std::move(c));
    crossing_nodes_.push_back(node.osm_id);
  }

  /// Sorted keys of the grid cells that add_intersections() looks in.
  std::vector<std::int64_t> cells_along_crossing_ways() const {
    std::vector<std::int64_t> keys;
    for (const CrossingWay& way : network_.crossing_ways) {
      std::optional<PlanePoint> previous;
      for (std::int64_t id : way.node_ids) {
        const std::optional<PlanePoint> here = locate(id);
        if (previous && here) EdgeGrid::add_cells(*previous, *here, keys);
        previous = here;
      }
    }
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
  }

  bool is_crossing_node(std::int64_t id) const {
    return std::binary_search(crossing_nodes_.begin(), crossing_nodes_.end(), id);
  }

  std::optional<PlanePoint> locate(std::int64_t id) const {
    const NodeLocation* location = network_.find_location(id);
    if (!location) {
      const auto& extra = network_.crossing_way_locations;
      const auto it =
          std::lower_bound(extra.begin(), extra.end(), id,
                           [](const NodeLocation& n, std::int64_t v) { return n.osm_id < v; });
      if (it == extra.end() || it->osm_id != id) return std::nullopt;
      location = &*it;
    }
    const geo::UtmPoint p = geo::wgs84_to_utm(location->lat_deg, location->lon_deg, graph_.zone);
    return PlanePoint{p.easting_m, p.northing_m};
  }

  void add_way(const CrossingWay& way, const EdgeGrid& grid, std::vector<Crossing>& out) {
    const CrossingKind kind = way_crossing_kind(way.tags);
    const KerbFacts& kerb =
        way_kerbs_[static_cast<std::size_t>(&way - network_.crossing_ways.data())];
    const std::size_t first_new = out.size();
    std::vector<PlanePoint> taken;  // places of this way already represented
    // Shared nodes: the way meets the road by node identity.
    for (std::int64_t id : way.node_ids) {
      const auto it = places_.find(id);
      if (it == places_.end()) continue;
      Crossing c = crossing_at(graph_, it->second);
      taken.push_back(c.point);
      if (is_crossing_node(id)) continue;  // the node's own row stands for it
      c.osm_id = way.osm_id;
      c.osm_type = "way";
      c.kind = kind;
      out.push_back(std::move(c));
    }
    add_intersections(way, kind, grid, taken, out);
    for (std::size_t i = first_new; i < out.size(); ++i) out[i].kerb = kerb;
  }

  /// Places where the way's edges cross road edges without a shared node.
  void add_intersections(const CrossingWay& way, const CrossingKind& kind, const EdgeGrid& grid,
                         std::vector<PlanePoint>& taken, std::vector<Crossing>& out) {
    std::optional<PlanePoint> previous;
    for (std::int64_t id : way.node_ids) {
      const std::optional<PlanePoint> here = locate(id);
      if (previous && here) {
        grid.near(*previous, *here, [&](const EdgeGrid::Edge& e) {
          const RoadPiece& piece = graph_.pieces[e.piece];
          const PlanePoint a = piece.points[e.edge], b = piece.points[e.edge + 1];
          const auto hit = intersect(a, b, *previous, *here);
          if (!hit) return;
          const PlanePoint point{a.x + hit->first * (b.x - a.x), a.y + hit->first * (b.y - a.y)};
          for (const PlanePoint& t : taken) {
            if (distance(t, point) < kSamePlaceM) return;
          }
          taken.push_back(point);
          double offset_m = hit->first * distance(a, b);
          for (std::size_t k = 0; k < e.edge; ++k)
            offset_m += distance(piece.points[k], piece.points[k + 1]);
          Crossing c;
          c.osm_id = way.osm_id;
          c.osm_type = "way";
          c.kind = kind;
          c.point = point;
          c.piece_index = e.piece;
          c.offset_in_piece_m = offset_m;
          c.segment_id = segment_at(graph_, piece, offset_m);
          out.push_back(std::move(c));
        });
      }
      previous = here;
    }
  }

  const RoadNetwork& network_;
  const RoadGraph& graph_;
  std::unordered_map<std::int64_t, std::vector<GraphPlace>> places_;
  std::vector<std::int64_t> crossing_nodes_;  // sorted: tagged_nodes are in id order
  std::vector<KerbFacts> way_kerbs_;          // per crossing way: its tags' and its nodes'
  std::unordered_map<std::int64_t, std::vector<std::size_t>> ways_through_;  // node -> ways
};

}  // namespace

std::optional<CrossingKind> node_crossing_kind(const Tags& tags) {
  const std::string_view tactile = tag_value(tags, "tactile_paving");
  const bool paved_for_crossing = tactile == "yes" || tactile == "contrasted" ||
                                  tactile == "primitive" || tactile == "incorrect";
  const bool marked = tag_value(tags, "highway") == "crossing" ||
                      !tag_value(tags, "crossing").empty() ||
                      !tag_value(tags, "crossing:markings").empty() ||
                      !tag_value(tags, "crossing:signals").empty() ||
                      !tag_value(tags, "crossing_ref").empty() || paved_for_crossing;
  if (!marked) return std::nullopt;
  return kind_from_tags(tags);
}

CrossingKind way_crossing_kind(const Tags& tags) {
  return kind_from_tags(tags);
}

std::vector<Crossing> find_crossings(const RoadNetwork& network, const RoadGraph& graph) {
  std::vector<Crossing> crossings = CrossingFinder(network, graph).find();
  // Node rows come first (in id order), way rows in way order and then along each way.
  std::stable_sort(crossings.begin(), crossings.end(), [](const Crossing& a, const Crossing& b) {
    return a.osm_type != b.osm_type ? a.osm_type < b.osm_type : a.osm_id < b.osm_id;
  });
  return crossings;
}

void assign_crossing_distances(RoadGraph& graph, const std::vector<Crossing>& crossings) {
  // Multi-source Dijkstra over the pieces, seeded at both ends of each crossing's piece. The
  // nodes by their position in the sorted incidence table (ids ascend with it, so the queue
  // breaks ties as it would by id), not in hash maps: ~130 bytes a node at country scale.
  const Incidences incidences(graph);
  std::vector<double> node_distance(incidences.node_count(),
                                    std::numeric_limits<double>::infinity());
  std::unordered_map<std::size_t, std::vector<double>> on_piece;  // crossing offsets per piece
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  const auto relax = [&](std::int64_t node, double d) {
    const std::size_t index = incidences.index_of(node);
    if (node_distance[index] <= d) return;
    node_distance[index] = d;
    queue.push({d, index});
  };
  for (const Crossing& c : crossings) {
    if (!c.kind.designated) continue;
    const RoadPiece& piece = graph.pieces[c.piece_index];
    on_piece[c.piece_index].push_back(c.offset_in_piece_m);
    relax(piece.from_node_id, c.offset_in_piece_m);
    relax(piece.to_node_id, piece.length_m - c.offset_in_piece_m);
  }
  while (!queue.empty()) {
    const auto [d, index] = queue.top();
    queue.pop();
    if (d > node_distance[index]) continue;
    // In piece order, from-end first: the order the neighbours were visited in before.
    for (const Incidence& end : incidences.at_index(index)) {
      const RoadPiece& piece = graph.pieces[end.piece];
      relax(end.at_end ? piece.from_node_id : piece.to_node_id, d + piece.length_m);
    }
  }
  const auto at = [&](std::int64_t node) { return node_distance[incidences.index_of(node)]; };
  // Piece by piece on every core (each writes only its own segments); its ends' distances
  // looked up once, not for each of its segments (a binary search each).
  constexpr std::size_t kChunk = 256;
  parallel_for<NoState>(
      graph.pieces.size(),
      [&](std::size_t p, NoState&) {
        const RoadPiece& piece = graph.pieces[p];
        const auto own = on_piece.find(p);
        const double from_m = at(piece.from_node_id), to_m = at(piece.to_node_id);
        for (std::size_t k = 0; k < piece.segment_count; ++k) {
          Segment& s = graph.segments[piece.first_segment + k];
          // From the midpoint, as junction_distance_m: where a robot crossing "here" stands.
          const double mid = graph.offset_in_piece_m(s) + 0.5 * graph.length_m(s);
          double d = std::min(mid + from_m, piece.length_m - mid + to_m);
          if (own != on_piece.end()) {
            for (double offset : own->second) d = std::min(d, std::abs(mid - offset));
          }
          if (std::isfinite(d)) s.crossing_distance_m = d;
        }
      },
      kChunk);
}

namespace {

/// Merges `facts` into the segments of `piece` that hold `offset_m` or whose midpoint lies
/// within `reach_m` of it along the piece.
void add_kerb_place(RoadGraph& graph, std::size_t piece_index, double offset_m,
                    const KerbFacts& facts, double reach_m) {
  const RoadPiece& piece = graph.pieces[piece_index];
  for (std::size_t k = 0; k < piece.segment_count; ++k) {
    const std::size_t index = piece.first_segment + k;
    const Segment& s = graph.segments[index];
    const double start_m = graph.offset_in_piece_m(s);
    const double length_m = graph.length_m(s);
    const bool holds = offset_m >= start_m && offset_m <= start_m + length_m;
    // The epsilon: a place exactly at the limit (a node between two 10 m segments is 5 m from
    // both midpoints) reaches both, as the crossing bonus does.
    const bool near = std::abs(start_m + 0.5 * length_m - offset_m) <= reach_m + 1e-6;
    if (holds || near) merge_kerb_facts(graph.kerbs[index], facts);
  }
}

/// The midpoint of a polyline and its direction there (ENU yaw, radians).
std::pair<PlanePoint, double> midpoint_and_yaw(std::span<const PlanePoint> line) {
  double total_m = 0.0;
  for (std::size_t i = 1; i < line.size(); ++i) total_m += distance(line[i - 1], line[i]);
  double left_m = 0.5 * total_m;
  for (std::size_t i = 1; i < line.size(); ++i) {
    const double edge_m = distance(line[i - 1], line[i]);
    if (left_m <= edge_m || i + 1 == line.size()) {
      const double t = edge_m > 0.0 ? std::clamp(left_m / edge_m, 0.0, 1.0) : 0.0;
      const PlanePoint a = line[i - 1], b = line[i];
      return {{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)}, std::atan2(b.y - a.y, b.x - a.x)};
    }
    left_m -= edge_m;
  }
  return {line.front(), 0.0};
}

/// The footway=sidewalk edges in a uniform grid of kSidewalkCellM cells.
constexpr double kSidewalkCellM = 25.0;

std::int64_t sidewalk_cell_key(std::int64_t x, std::int64_t y) {
  return x * 4'000'003 + y;
}

std::int64_t sidewalk_cell(double v) {
  return static_cast<std::int64_t>(std::floor(v / kSidewalkCellM));
}

using SidewalkEdge = std::pair<PlanePoint, PlanePoint>;

std::unordered_map<std::int64_t, std::vector<SidewalkEdge>> sidewalk_grid(
    const RoadNetwork& network, const geo::UtmZone& zone) {
  std::unordered_map<std::int64_t, std::vector<SidewalkEdge>> grid;
  const auto locate = [&](std::int64_t id) -> std::optional<PlanePoint> {
    const NodeLocation* location = network.find_location(id);
    if (!location) {
      const auto& extra = network.crossing_way_locations;
      const auto it =
          std::lower_bound(extra.begin(), extra.end(), id,
                           [](const NodeLocation& n, std::int64_t v) { return n.osm_id < v; });
      if (it == extra.end() || it->osm_id != id) return std::nullopt;
      location = &*it;
    }
    const geo::UtmPoint p = geo::wgs84_to_utm(location->lat_deg, location->lon_deg, zone);
    return PlanePoint{p.easting_m, p.northing_m};
  };
  // The projections (most of the work) on every core into one flat array, way after way; the
  // grid is then filled in way order on this thread, so its cells list edges as before.
  const std::vector<SidewalkWay>& ways = network.sidewalk_ways;
  std::vector<std::size_t> first(ways.size() + 1, 0);
  for (std::size_t w = 0; w < ways.size(); ++w) first[w + 1] = first[w] + ways[w].node_ids.size();
  std::vector<std::optional<PlanePoint>> points(first.back());
  constexpr std::size_t kChunk = 64;
  parallel_for<NoState>(
      ways.size(),
      [&](std::size_t w, NoState&) {
        for (std::size_t k = 0; k < ways[w].node_ids.size(); ++k) {
          points[first[w] + k] = locate(ways[w].node_ids[k]);
        }
      },
      kChunk);
  for (std::size_t w = 0; w < ways.size(); ++w) {
    std::optional<PlanePoint> previous;
    for (std::size_t k = first[w]; k < first[w + 1]; ++k) {
      const std::optional<PlanePoint> here = points[k];
      if (previous && here) {
        for (std::int64_t x = sidewalk_cell(std::min(previous->x, here->x));
             x <= sidewalk_cell(std::max(previous->x, here->x)); ++x) {
          for (std::int64_t y = sidewalk_cell(std::min(previous->y, here->y));
               y <= sidewalk_cell(std::max(previous->y, here->y)); ++y) {
            grid[sidewalk_cell_key(x, y)].push_back({*previous, *here});
          }
        }
      }
      previous = here;
    }
  }
  return grid;
}

/// +1 when a sidewalk edge near `mid` (within `reach_m`, within 30 degrees of `yaw_rad`) lies
/// left of the road direction, -1 right; 0 for none. Both: 2.
int sidewalks_near(const std::unordered_map<std::int64_t, std::vector<SidewalkEdge>>& grid,
                   PlanePoint mid, double yaw_rad, double reach_m) {
  const double ux = std::cos(yaw_rad), uy = std::sin(yaw_rad);
  const double max_sin = std::sin(30.0 * geo::kPi / 180.0);
  bool left = false, right = false;
  for (std::int64_t x = sidewalk_cell(mid.x - reach_m); x <= sidewalk_cell(mid.x + reach_m); ++x) {
    for (std::int64_t y = sidewalk_cell(mid.y - reach_m); y <= sidewalk_cell(mid.y + reach_m);
         ++y) {
      const auto it = grid.find(sidewalk_cell_key(x, y));
      if (it == grid.end()) continue;
      for (const auto& [a, b] : it->second) {
        const double ex = b.x - a.x, ey = b.y - a.y, length_m = std::hypot(ex, ey);
        if (length_m <= 0.0) continue;
        // Parallel to the road: the sine of the angle between them is small.
        if (std::abs(ux * ey - uy * ex) / length_m > max_sin) continue;
        const double t =
            std::clamp(((mid.x - a.x) * ex + (mid.y - a.y) * ey) / (length_m * length_m), 0.0, 1.0);
        const PlanePoint closest{a.x + t * ex, a.y + t * ey};
        if (distance(closest, mid) > reach_m) continue;
        const double side = ux * (closest.y - mid.y) - uy * (closest.x - mid.x);
        (side > 0.0 ? left : right) = true;
      }
    }
  }
  return left && right ? 2 : left ? 1 : right ? -1 : 0;
}

}  // namespace

void assign_kerbs(RoadGraph& graph, const RoadNetwork& network,
                  const std::vector<Crossing>& crossings, double reach_m) {
  std::vector<std::int64_t> crossing_node_ids;
  for (const Crossing& c : crossings) {
    if (c.osm_type == "node") crossing_node_ids.push_back(c.osm_id);
    if (!c.kerb.empty()) add_kerb_place(graph, c.piece_index, c.offset_in_piece_m, c.kerb, reach_m);
  }
  std::sort(crossing_node_ids.begin(), crossing_node_ids.end());
  // Kerb nodes on the road itself (barrier=kerb where a footway meets it) that are no crossing.
  std::vector<std::int64_t> kerb_nodes;
  for (const TaggedNode& node : network.tagged_nodes) {
    if (std::binary_search(crossing_node_ids.begin(), crossing_node_ids.end(), node.osm_id))
      continue;
    if (!kerb_facts(node.tags).empty()) kerb_nodes.push_back(node.osm_id);
  }
  if (kerb_nodes.empty()) return;
  const auto places = place_nodes(graph, kerb_nodes);
  for (std::int64_t id : kerb_nodes) {
    const auto it = places.find(id);
    if (it == places.end()) continue;
    const KerbFacts facts = kerb_facts(*node_tags(network, id));
    for (const GraphPlace& place : it->second) {
      add_kerb_place(graph, place.piece, place.offset_m, facts, reach_m);
    }
  }
}

void assign_sidewalks(RoadGraph& graph, const RoadNetwork& network, double sidewalk_reach_m) {
  bool any_unknown = false;
  for (RoadPiece& piece : graph.pieces) {
    piece.sidewalks = sidewalk_sides(network.ways[piece.way_index].tags);
    any_unknown = any_unknown || !piece.sidewalks.left || !piece.sidewalks.right;
  }
  if (!any_unknown || network.sidewalk_ways.empty()) return;
  const auto grid = sidewalk_grid(network, graph.zone);
  // Piece by piece on every core: each reads the grid and its own segments and writes only its
  // own sides.
  constexpr std::size_t kChunk = 256;
  parallel_for<NoState>(
      graph.pieces.size(),
      [&](std::size_t p, NoState&) {
        RoadPiece& piece = graph.pieces[p];
        if (piece.sidewalks.left && piece.sidewalks.right) return;
        const double reach_m = 0.5 * piece.width_m.value_or(6.0f) + sidewalk_reach_m;
        std::size_t left_votes = 0, right_votes = 0;
        for (std::size_t k = 0; k < piece.segment_count; ++k) {
          const Segment& s = graph.segments[piece.first_segment + k];
          const auto [mid, yaw] = midpoint_and_yaw(graph.line(s));
          const int near = sidewalks_near(grid, mid, yaw, reach_m);
          left_votes += (near == 1 || near == 2) ? 1 : 0;
          right_votes += (near == -1 || near == 2) ? 1 : 0;
        }
        // At least half of the segments: a sidewalk that only touches the piece's end (the
        // pavement of a side street) does not count.
        if (!piece.sidewalks.left && 2 * left_votes >= piece.segment_count && left_votes > 0)
          piece.sidewalks.left = true;
        if (!piece.sidewalks.right && 2 * right_votes >= piece.segment_count && right_votes > 0)
          piece.sidewalks.right = true;
      },
      kChunk);
}

}  // namespace roadcross::preprocess
