#include "roadcross/preprocess/graph/strokes.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <unordered_map>
#include <utility>

#include "roadcross/preprocess/common/parallel.hpp"

namespace roadcross::preprocess {
namespace {

struct Step {
  std::size_t piece;
  bool reversed;
};

std::int64_t exit_node(const RoadPiece& piece, bool reversed) {
  return reversed ? piece.from_node_id : piece.to_node_id;
}

/// Follows the chain from `node`, leaving `came_from`, while nodes have degree 2.
/// Returns the steps in walking order; `closed` is set when the walk returns to `start_piece`.
std::vector<Step> walk(const RoadGraph& graph, const Incidences& incidences, std::int64_t node,
                       Incidence came_from, std::size_t start_piece, std::vector<char>& visited,
                       bool& closed) {
  std::vector<Step> steps;
  while (true) {
    const std::span<const Incidence> ends = incidences.at(node);
    if (ends.size() != 2) break;
    const Incidence& a = ends[0];
    const Incidence& b = ends[1];
    const Incidence next = (a.piece == came_from.piece && a.at_end == came_from.at_end) ? b : a;
    if (next.piece == start_piece) {
      closed = true;
      break;
    }
    if (visited[next.piece]) break;
    visited[next.piece] = 1;
    // Entering at its to-node means walking the piece backwards.
    const bool reversed = next.at_end;
    steps.push_back({next.piece, reversed});
    node = exit_node(graph.pieces[next.piece], reversed);
    came_from = {next.piece, !next.at_end};
  }
  return steps;
}

Stroke make_stroke(const RoadGraph& graph, const std::vector<Step>& steps, bool closed) {
  Stroke stroke;
  stroke.closed = closed;
  for (const Step& step : steps) {
    const RoadPiece& piece = graph.pieces[step.piece];
    std::vector<PlanePoint> pts = piece.points;
    if (step.reversed) std::reverse(pts.begin(), pts.end());
    const std::size_t skip = stroke.points.empty() ? 0 : 1;  // the joint is already there
    stroke.points.insert(stroke.points.end(), pts.begin() + static_cast<std::ptrdiff_t>(skip),
                         pts.end());
    const double base = stroke.length_m;
    std::vector<StrokeSegment> in_piece;
    for (std::size_t k = 0; k < piece.segment_count; ++k) {
      const std::size_t index = piece.first_segment + k;
      const Segment& s = graph.segments[index];
      const double a = graph.offset_in_piece_m(s), b = a + graph.length_m(s);
      in_piece.push_back(step.reversed ? StrokeSegment{index, true, base + piece.length_m - b,
                                                       base + piece.length_m - a}
                                       : StrokeSegment{index, false, base + a, base + b});
    }
    if (step.reversed) std::reverse(in_piece.begin(), in_piece.end());
    stroke.segments.insert(stroke.segments.end(), in_piece.begin(), in_piece.end());
    stroke.length_m += piece.length_m;
  }
  return stroke;
}

}  // namespace

std::vector<Stroke> build_strokes(const RoadGraph& graph) {
  std::vector<Stroke> strokes;
  for_each_stroke(graph, [&](const Stroke& stroke) { strokes.push_back(stroke); });
  return strokes;
}

namespace {

/// Calls chain(steps, closed) for the pieces of every stroke, in for_each_stroke's order.
template <typename Chain>
void for_each_chain(const RoadGraph& graph, const Incidences& incidences, Chain&& chain) {
  std::vector<char> visited(graph.pieces.size(), 0);
  for (std::size_t p = 0; p < graph.pieces.size(); ++p) {
    if (visited[p]) continue;
    visited[p] = 1;
    const RoadPiece& piece = graph.pieces[p];
    bool closed = false;
    // In stroke order: the walk back from the from-node (reversed and flipped), the piece, the
    // walk on from the to-node. (A vector: a deque would allocate ~600 bytes a stroke.)
    std::vector<Step> steps;
    // A piece that starts and ends at the same node is a ring of its own.
    if (piece.from_node_id != piece.to_node_id) {
      std::vector<Step> ahead =
          walk(graph, incidences, piece.to_node_id, {p, true}, p, visited, closed);
      if (!closed) {
        steps = walk(graph, incidences, piece.from_node_id, {p, false}, p, visited, closed);
        std::reverse(steps.begin(), steps.end());
        for (Step& s : steps) s.reversed = !s.reversed;  // walked backwards: flip to stroke order
      }
      steps.reserve(steps.size() + 1 + ahead.size());
      steps.push_back({p, false});
      steps.insert(steps.end(), ahead.begin(), ahead.end());
    } else {
      steps.push_back({p, false});
      closed = incidences.at(piece.from_node_id).size() == 2;
    }
    chain(std::move(steps), closed);
  }
}

}  // namespace

void for_each_stroke(const RoadGraph& graph, const std::function<void(const Stroke&)>& visit) {
  const Incidences incidences = incidences_of(graph);
  for_each_chain(graph, incidences, [&](const std::vector<Step>& steps, bool closed) {
    visit(make_stroke(graph, steps, closed));
  });
}

void for_each_stroke_parallel(const RoadGraph& graph, const Incidences& incidences,
                              const std::function<void(const Stroke&)>& visit) {
  // This thread only finds each stroke's pieces (the walk needs the pieces visited before);
  // building the strokes' lines and visiting them, most of the work, run on every core. Enough
  // segments a batch that a handover costs little beside the visits; few enough that two
  // batches held at once are nothing beside the graph.
  constexpr std::size_t kBatchSegments = 1 << 15;
  constexpr std::size_t kChunk = 16;
  struct Chain {
    std::vector<Step> steps;
    bool closed = false;
  };
  std::vector<Chain> filling, visiting;
  std::size_t filling_segments = 0;
  // Declared after the batches: an exception here waits for the visits of `visiting` first.
  std::future<void> visits;
  const auto hand_over = [&] {
    if (visits.valid()) visits.get();
    std::swap(filling, visiting);
    filling.clear();
    filling_segments = 0;
    visits = std::async(std::launch::async, [&graph, &visiting, &visit] {
      parallel_for<NoState>(
          visiting.size(),
          [&](std::size_t k, NoState&) {
            visit(make_stroke(graph, visiting[k].steps, visiting[k].closed));
          },
          kChunk);
    });
  };
  for_each_chain(graph, incidences, [&](std::vector<Step>&& steps, bool closed) {
    for (const Step& step : steps) filling_segments += graph.pieces[step.piece].segment_count;
    filling.push_back({std::move(steps), closed});
    if (filling_segments >= kBatchSegments) hand_over();
  });
  if (!filling.empty()) hand_over();
  if (visits.valid()) visits.get();
}

namespace {
/// Length of [a, b] inside [lo, hi].
double overlap(double a, double b, double lo, double hi) {
  return std::max(0.0, std::min(b, hi) - std::max(a, lo));
}
}  // namespace

std::vector<double> windowed_mean(const Stroke& stroke, const std::vector<double>& values,
                                  double half_length_m, double own_weight) {
  const std::vector<StrokeSegment>& segments = stroke.segments;
  const double total = stroke.length_m;
  // On a ring the window continues past the closing point: the stroke is seen shifted by
  // -total and +total as well (a window shorter than the ring never counts a segment twice).
  const std::vector<double> shifts =
      stroke.closed ? std::vector<double>{-total, 0.0, total} : std::vector<double>{0.0};
  std::vector<double> out(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const double mid = 0.5 * (segments[i].start_m + segments[i].end_m);
    const double lo = mid - half_length_m, hi = mid + half_length_m;
    double weighted = 0.0, length = 0.0;
    for (const double shift : shifts) {
      // Segments are in stroke order: start at the first one that ends after the window opens.
      auto it = std::partition_point(segments.begin(), segments.end(),
                                     [&](const StrokeSegment& x) { return x.end_m + shift <= lo; });
      for (; it != segments.end() && it->start_m + shift < hi; ++it) {
        const double value = values[static_cast<std::size_t>(it - segments.begin())];
        if (std::isnan(value)) continue;
        const bool is_own = shift == 0.0 && it == segments.begin() + static_cast<std::ptrdiff_t>(i);
        const double inside =
            overlap(it->start_m + shift, it->end_m + shift, lo, hi) * (is_own ? own_weight : 1.0);
        weighted += inside * value;
        length += inside;
      }
    }
    out[i] = length > 0.0 ? weighted / length : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

}  // namespace roadcross::preprocess
