#include "roadcross/preprocess/graph/segments.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "roadcross/preprocess/common/huge_pages.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/osm/road_network.hpp"

namespace roadcross::preprocess {

std::uint32_t NoteTable::index_of(const SegmentNotes& notes) {
  // The none pair is index 0 without being in the map (a default Segment's).
  if (notes == SegmentNotes{}) return 0;
  const auto [it, added] = index_.try_emplace(notes, 0);
  if (added) {
    if (pairs_.size() > std::numeric_limits<std::uint32_t>::max()) {
      index_.erase(it);
      throw std::length_error("more than 4 294 967 295 distinct segment notes: 32-bit indices");
    }
    it->second = static_cast<std::uint32_t>(pairs_.size());
    pairs_.push_back(notes);
  }
  return it->second;
}

double polyline_length_m(std::span<const PlanePoint> points) noexcept {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) {
    length += std::hypot(points[i].x - points[i - 1].x, points[i].y - points[i - 1].y);
  }
  return length;
}

geo::UtmZone choose_utm_zone(const RoadNetwork& network) {
  double min_lat = std::numeric_limits<double>::infinity(), max_lat = -min_lat;
  double min_lon = min_lat, max_lon = -min_lat;
  for (const NodeLocation& n : network.locations) {
    min_lat = std::min(min_lat, n.lat_deg);
    max_lat = std::max(max_lat, n.lat_deg);
    min_lon = std::min(min_lon, n.lon_deg);
    max_lon = std::max(max_lon, n.lon_deg);
  }
  return geo::standard_utm_zone(0.5 * (min_lat + max_lat), 0.5 * (min_lon + max_lon));
}

std::size_t segment_count_of(double piece_length_m, double max_segment_length_m) noexcept {
  // Equal parts: ceil with a tolerance so that a 20.000000001 m piece with a 10 m limit is 2.
  return static_cast<std::size_t>(
      std::max(1.0, std::ceil(piece_length_m / max_segment_length_m - 1e-9)));
}

namespace {

bool is_yes(std::string_view value) {
  return !value.empty() && value != "no" && value != "false" && value != "0";
}

bool way_is_oneway(const Tags& tags) {
  const std::string_view oneway = tag_value(tags, "oneway");
  if (oneway == "yes" || oneway == "1" || oneway == "true" || oneway == "-1") return true;
  if (oneway == "no") return false;
  const std::string_view junction = tag_value(tags, "junction");
  return junction == "roundabout" || junction == "circular";
}

bool way_is_tunnel(const Tags& tags) {
  return is_yes(tag_value(tags, "tunnel")) || tag_value(tags, "covered") == "yes";
}

/// A run of consecutive located, distinct nodes of one way.
struct NodeRun {
  std::vector<std::int64_t> ids;
  std::vector<PlanePoint> points;
};

/// The UTM points of RoadNetwork::locations, in the same order (sorted by OSM id): a lookup is
/// a binary search, and the table costs 16 bytes a node instead of a hash map's ~60.
class ProjectedNodes {
 public:
  ProjectedNodes(const std::vector<NodeLocation>& locations, const geo::UtmZone& zone)
      : locations_(locations), points_(locations.size()) {
    // On every core: the exact projection (thousands of instructions a node) is most of the
    // segmenting's time, and each node's point is its own.
    constexpr std::size_t kNodesPerTask = 4096;
    const std::size_t tasks = (locations.size() + kNodesPerTask - 1) / kNodesPerTask;
    parallel_for<NoState>(tasks, [&](std::size_t task, NoState&) {
      const std::size_t end = std::min(locations.size(), (task + 1) * kNodesPerTask);
      for (std::size_t i = task * kNodesPerTask; i < end; ++i) {
        const geo::UtmPoint p = geo::wgs84_to_utm(locations[i].lat_deg, locations[i].lon_deg, zone);
        points_[i] = {p.easting_m, p.northing_m};
      }
    });
  }
  const PlanePoint* find(std::int64_t id) const {
    const auto it = std::lower_bound(
        locations_.begin(), locations_.end(), id,
        [](const NodeLocation& n, std::int64_t wanted) { return n.osm_id < wanted; });
    if (it == locations_.end() || it->osm_id != id) return nullptr;
    return &points_[static_cast<std::size_t>(it - locations_.begin())];
  }

 private:
  const std::vector<NodeLocation>& locations_;
  std::vector<PlanePoint> points_;
};

/// Whether a node list visits some node twice (a ring, a loop, a retrace).
bool revisits_a_node(const std::vector<std::int64_t>& ids) {
  thread_local std::vector<std::int64_t> sorted;  // reused: most ways are a dozen nodes
  sorted.assign(ids.begin(), ids.end());
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

/// Splits a way's node list into runs of located nodes, dropping consecutive duplicates and
/// every edge the way already drew (a way that goes back and forth between two nodes draws one
/// road, not 100 000 parallel pieces meeting at two nodes, which would make every walk along the
/// network, e.g. the sight stage's, quadratic).
std::vector<NodeRun> located_runs(const RoadWay& way, const ProjectedNodes& projected,
                                  std::uint64_t& dropped_refs) {
  std::vector<NodeRun> runs(1);
  const bool check_retrace = revisits_a_node(way.node_ids);
  std::set<std::pair<std::int64_t, std::int64_t>> drawn;  // edges as (smaller, larger) node id
  for (std::int64_t id : way.node_ids) {
    const PlanePoint* point = projected.find(id);
    if (!point) {
      ++dropped_refs;
      if (!runs.back().ids.empty()) runs.emplace_back();
      continue;
    }
    if (!runs.back().ids.empty() && runs.back().ids.back() == id) continue;
    if (check_retrace && !runs.back().ids.empty()) {
      const std::int64_t from = runs.back().ids.back();
      if (!drawn.insert({std::min(from, id), std::max(from, id)}).second) {
        runs.emplace_back();  // an edge drawn before: the run ends, the next starts here
      }
    }
    NodeRun& run = runs.back();
    run.ids.push_back(id);
    run.points.push_back(*point);
  }
  std::erase_if(runs, [](const NodeRun& r) { return r.ids.size() < 2; });
  return runs;
}

/// Point at distance `s` (metres) along `points`, with the index of the edge it lies on.
PlanePoint point_at(const std::vector<PlanePoint>& points, const std::vector<double>& cumulative,
                    double s, std::size_t& edge) {
  while (edge + 2 < points.size() && cumulative[edge + 1] < s) ++edge;
  const double edge_length = cumulative[edge + 1] - cumulative[edge];
  const double t =
      edge_length > 0.0 ? std::clamp((s - cumulative[edge]) / edge_length, 0.0, 1.0) : 0.0;
  return {points[edge].x + t * (points[edge + 1].x - points[edge].x),
          points[edge].y + t * (points[edge + 1].y - points[edge].y)};
}

void cut_piece(RoadGraph& graph, std::size_t piece_index, const RoadWay& way, double max_length_m) {
  RoadPiece& piece = graph.pieces[piece_index];
  const std::vector<PlanePoint>& pts = piece.points;
  std::vector<double> cumulative(pts.size(), 0.0);
  for (std::size_t i = 1; i < pts.size(); ++i) {
    cumulative[i] =
        cumulative[i - 1] + std::hypot(pts[i].x - pts[i - 1].x, pts[i].y - pts[i - 1].y);
  }
  // The same sum as polyline_length_m (pass 2 counted the segments with it).
  piece.length_m = cumulative.back();
  const std::size_t count = segment_count_of(piece.length_m, max_length_m);
  const double part_m = piece.length_m / static_cast<double>(count);
  piece.first_segment = graph.segments.size();
  piece.segment_count = count;

  piece.osm_way_id = way.osm_id;
  piece.highway = graph.text.intern_text(way.highway);
  const std::string_view name_tag = tag_value(way.tags, "name");
  piece.name = name_tag.empty() ? InternedText() : graph.text.intern_text(name_tag);
  const std::string_view ref_tag = tag_value(way.tags, "ref");
  piece.ref = ref_tag.empty() ? InternedText() : graph.text.intern_text(ref_tag);
  const bool oneway = way_is_oneway(way.tags);
  const bool tunnel = way_is_tunnel(way.tags);
  const bool bridge = is_yes(tag_value(way.tags, "bridge"));
  std::size_t edge = 0;
  std::vector<PlanePoint>& line = graph.segment_points;
  PlanePoint from_point = pts.front();
  for (std::size_t k = 0; k < count; ++k) {
    // RoadGraph::offset_in_piece_m and length_m derive the segment's span with the same
    // arithmetic; its id and end node ids follow from its index and piece (RoadGraph).
    const double start_m = part_m * static_cast<double>(k);
    const double end_m = (k + 1 == count) ? piece.length_m : part_m * static_cast<double>(k + 1);
    Segment segment;
    // A 32-bit index (checked in build_road_graph).
    segment.piece_index = static_cast<std::uint32_t>(piece_index);
    segment.oneway = oneway;
    segment.tunnel = tunnel;
    segment.bridge = bridge;
    // The line starts at the previous segment's last point (already in the pool), if any.
    if (k == 0) line.push_back(from_point);
    const std::size_t first_point = line.size() - 1;
    // Interior OSM vertices strictly inside (start, end) keep the road's shape.
    std::size_t vertex = edge + 1;
    while (vertex + 1 < pts.size() && cumulative[vertex] <= start_m) ++vertex;
    for (; vertex + 1 < pts.size() && cumulative[vertex] < end_m; ++vertex) {
      line.push_back(pts[vertex]);
    }
    const bool last = (k + 1 == count);
    const PlanePoint to_point = last ? pts.back() : point_at(pts, cumulative, end_m, edge);
    line.push_back(to_point);
    if (line.size() > std::numeric_limits<std::uint32_t>::max()) {
      throw std::length_error("OSM way " + std::to_string(way.osm_id) +
                              ": more than 4 294 967 295 segment points in all: segment line "
                              "indices are 32-bit");
    }
    // The point count is derived (RoadGraph::line): the line ends where the next one starts.
    segment.first_point = static_cast<std::uint32_t>(first_point);
    from_point = to_point;
    graph.segments.push_back(std::move(segment));
  }
}

}  // namespace

RoadGraph build_road_graph(const RoadNetwork& network, geo::UtmZone zone,
                           double max_segment_length_m) {
  RoadGraph graph;
  graph.zone = zone;
  if (network.ways.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("more than 4 294 967 295 road ways: segment indices are 32-bit");
  }
  auto projected = std::make_unique<const ProjectedNodes>(network.locations, zone);
  // The located runs are recomputed in each of the three passes below rather than kept: a copy
  // of every node id and point of every way would sit beside the segment table at the peak.

  // Passes 1 and 2 walk the ways in chunks on every core, each chunk's results kept apart and
  // joined in way order: the same lists as one walk.
  constexpr std::size_t kWaysPerTask = 1024;
  const std::size_t tasks = (network.ways.size() + kWaysPerTask - 1) / kWaysPerTask;
  const auto ways_of = [&](std::size_t task) {
    return std::pair(task * kWaysPerTask, std::min(network.ways.size(), (task + 1) * kWaysPerTask));
  };

  // Pass 1: the graph's inner nodes, those used more than once across all runs (sorted ids).
  struct RunNodes {
    std::vector<std::int64_t> ids;
    std::uint64_t dropped_refs = 0;
    std::size_t dropped_ways = 0;
  };
  std::vector<RunNodes> run_nodes(tasks);
  parallel_for<NoState>(tasks, [&](std::size_t task, NoState&) {
    RunNodes& out = run_nodes[task];
    const auto [first, last] = ways_of(task);
    for (std::size_t w = first; w < last; ++w) {
      const std::vector<NodeRun> runs = located_runs(network.ways[w], *projected, out.dropped_refs);
      if (runs.empty()) ++out.dropped_ways;
      for (const NodeRun& run : runs) {
        // A closed way's last node is its first: count it once so a ring alone is not a junction.
        const bool ring = run.ids.back() == run.ids.front();
        out.ids.insert(out.ids.end(), run.ids.begin(), run.ids.end() - (ring ? 1 : 0));
      }
    }
  });
  std::vector<std::int64_t> junctions;
  std::size_t run_node_count = 0;
  for (const RunNodes& part : run_nodes) run_node_count += part.ids.size();
  junctions.reserve(run_node_count);
  for (RunNodes& part : run_nodes) {
    junctions.insert(junctions.end(), part.ids.begin(), part.ids.end());
    graph.dropped_node_refs += part.dropped_refs;
    graph.dropped_ways += part.dropped_ways;
    std::vector<std::int64_t>().swap(part.ids);  // freed as copied: not held twice
  }
  std::sort(junctions.begin(), junctions.end());
  auto kept = junctions.begin();
  for (auto it = junctions.begin(); it != junctions.end();) {
    const auto next = std::find_if(it, junctions.end(), [&](std::int64_t id) { return id != *it; });
    if (next - it >= 2) *kept++ = *it;
    it = next;
  }
  junctions.erase(kept, junctions.end());
  junctions.shrink_to_fit();
  const auto is_split_node = [&](std::int64_t id) {
    return std::binary_search(junctions.begin(), junctions.end(), id);
  };

  // Pass 2: the pieces (runs split at inner nodes), their lengths and segment counts, so that
  // the segment table is allocated once at its exact size (growing it by doubling would hold
  // the old and the new table at once: 1.5 times the table at the peak).
  struct Pieces {
    std::vector<RoadPiece> pieces;
    std::size_t segments = 0, points = 0;
  };
  std::vector<Pieces> pieces_of_task(tasks);
  parallel_for<NoState>(tasks, [&](std::size_t task, NoState&) {
    Pieces& out = pieces_of_task[task];
    std::uint64_t ignored_refs = 0;
    const auto [first, last] = ways_of(task);
    for (std::size_t w = first; w < last; ++w) {
      for (const NodeRun& run : located_runs(network.ways[w], *projected, ignored_refs)) {
        std::size_t start = 0;
        for (std::size_t i = 1; i < run.ids.size(); ++i) {
          const bool end_of_run = (i + 1 == run.ids.size());
          if (!end_of_run && !is_split_node(run.ids[i])) continue;
          RoadPiece piece;
          piece.way_index = w;
          piece.from_node_id = run.ids[start];
          piece.to_node_id = run.ids[i];
          piece.points.assign(run.points.begin() + static_cast<std::ptrdiff_t>(start),
                              run.points.begin() + static_cast<std::ptrdiff_t>(i) + 1);
          piece.node_ids.assign(run.ids.begin() + static_cast<std::ptrdiff_t>(start),
                                run.ids.begin() + static_cast<std::ptrdiff_t>(i) + 1);
          piece.length_m = polyline_length_m(piece.points);
          piece.segment_count = segment_count_of(piece.length_m, max_segment_length_m);
          out.segments += piece.segment_count;
          // At most: the start, each segment's end and every inner vertex once.
          out.points += piece.segment_count + piece.points.size() - 1;
          out.pieces.push_back(std::move(piece));
          start = i;
        }
      }
    }
  });
  std::size_t segment_total = 0, point_total = 0, piece_total = 0;
  for (const Pieces& part : pieces_of_task) piece_total += part.pieces.size();
  graph.pieces.reserve(piece_total);
  for (Pieces& part : pieces_of_task) {
    segment_total += part.segments;
    point_total += part.points;
    std::move(part.pieces.begin(), part.pieces.end(), std::back_inserter(graph.pieces));
    std::vector<RoadPiece>().swap(part.pieces);
  }
  graph.pieces.shrink_to_fit();
  if (graph.pieces.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("more than 4 294 967 295 road pieces: Segment::piece_index is 32-bit");
  }
  std::vector<std::int64_t>().swap(junctions);
  // Pass 3 cuts the pieces' own points: the nodes' projection (16 bytes a node) is not needed.
  projected.reset();

  // Pass 3: the segments, in piece order.
  graph.segments.reserve(segment_total);
  graph.segment_points.reserve(point_total);
  // Both filled once, front to back, just below: one fault a 2 MiB page, not a 4 KiB one.
  advise_huge_pages(graph.segments);
  advise_huge_pages(graph.segment_points);
  // Their pages are zeroed by the kernel on the other core (idle here) as this one fills them.
  const PrefaultBeside segments_ahead(graph.segments.data(),
                                      graph.segments.capacity() * sizeof(Segment));
  const PrefaultBeside points_ahead(graph.segment_points.data(),
                                    graph.segment_points.capacity() * sizeof(PlanePoint));
  for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
    const RoadPiece& piece = graph.pieces[p];
    ++graph.degree[piece.from_node_id];
    ++graph.degree[piece.to_node_id];
    cut_piece(graph, p, network.ways[piece.way_index], max_segment_length_m);
  }
  return graph;
}

Incidences::Incidences(const RoadGraph& graph) {
  std::vector<std::pair<std::int64_t, Incidence>> ends;
  ends.reserve(2 * graph.pieces.size());
  for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
    ends.push_back({graph.pieces[p].from_node_id, {p, false}});
    ends.push_back({graph.pieces[p].to_node_id, {p, true}});
  }
  // Stable: each node keeps its ends in piece order, from-end first.
  std::stable_sort(ends.begin(), ends.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  ends_.reserve(ends.size());
  for (std::size_t i = 0; i < ends.size(); ++i) {
    if (i == 0 || ends[i].first != ends[i - 1].first) {
      nodes_.push_back(ends[i].first);
      first_.push_back(i);
    }
    ends_.push_back(ends[i].second);
  }
  first_.push_back(ends_.size());
}

std::size_t Incidences::index_of(std::int64_t node) const noexcept {
  const auto it = std::lower_bound(nodes_.begin(), nodes_.end(), node);
  return it != nodes_.end() && *it == node ? static_cast<std::size_t>(it - nodes_.begin()) : npos;
}

std::span<const Incidence> Incidences::at(std::int64_t node) const noexcept {
  const std::size_t index = index_of(node);
  return index == npos ? std::span<const Incidence>() : at_index(index);
}

RoadBounds road_bounds(const RoadGraph& graph) {
  RoadBounds b;
  for (const Segment& s : graph.segments) {
    for (const PlanePoint& q : graph.line(s)) {
      b.min_e = std::min(b.min_e, q.x), b.max_e = std::max(b.max_e, q.x);
      b.min_n = std::min(b.min_n, q.y), b.max_n = std::max(b.max_n, q.y);
    }
  }
  return b;
}

}  // namespace roadcross::preprocess
