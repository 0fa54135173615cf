#include "roadcross/preprocess/context/crossings.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>

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
};

}  // namespace

std::optional<CrossingKind> node_crossing_kind(const Tags& tags) {
  const bool marked =
      tag_value(tags, "highway") == "crossing" || !tag_value(tags, "crossing").empty() ||
      !tag_value(tags, "crossing:markings").empty() ||
      !tag_value(tags, "crossing:signals").empty() || !tag_value(tags, "crossing_ref").empty();
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
  for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
    const RoadPiece& piece = graph.pieces[p];
    const auto own = on_piece.find(p);
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      Segment& s = graph.segments[piece.first_segment + k];
      // From the midpoint, as junction_distance_m: where a robot crossing "here" stands.
      const double mid = graph.offset_in_piece_m(s) + 0.5 * graph.length_m(s);
      double d =
          std::min(mid + at(piece.from_node_id), piece.length_m - mid + at(piece.to_node_id));
      if (own != on_piece.end()) {
        for (double offset : own->second) d = std::min(d, std::abs(mid - offset));
      }
      if (std::isfinite(d)) s.crossing_distance_m = d;
    }
  }
}

}  // namespace roadcross::preprocess
