// The road as an approaching driver follows it from a segment of the sight stage: a path along
// pieces through graph nodes onto the straightest continuation (RoadFollower), the pieces' leg
// lengths a thread keeps (LegLengths) and the tables they read. Internal to
// preprocess/src/sight/sight.cpp; a header so that the unit tests reach the pieces.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::preprocess::sight_detail {

inline PlanePoint lerp(const PlanePoint& a, const PlanePoint& b, double t) {
  return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

/// |b - a| in metres. The square root of the sum of squares, not std::hypot: the differences of
/// UTM coordinates (below 1e7 m) can neither overflow nor underflow when squared, so hypot's
/// scaling buys nothing here, and its call was ~1 % of the sight stage's instructions.
inline double distance_m(const PlanePoint& a, const PlanePoint& b) {
  const double dx = b.x - a.x, dy = b.y - a.y;
  return std::sqrt(dx * dx + dy * dy);
}

/// The road as an approaching driver follows it, from the robot's point outwards.
struct Path {
  std::vector<PlanePoint> points;
  std::vector<double> at_m;  ///< distance along the path of each point

  double length_m() const { return at_m.back(); }
  void add(const PlanePoint& p) { add(p, distance_m(points.back(), p)); }
  /// add(p) when step_m = distance_m(points.back(), p) is known.
  void add(const PlanePoint& p, double step_m) {
    if (step_m < 1e-9) return;  // joints and zero-length legs
    points.push_back(p);
    at_m.push_back(at_m.back() + step_m);
  }
};

/// The lengths of the legs of the pieces a thread's roads follow (distance_m of vertices k and
/// k + 1 at [k]), kept for the pieces met last (direct-mapped by piece index): a thread's
/// consecutive segments, 13 a piece on average, follow the same pieces again and again, and a
/// hypot per vertex followed was ~5 % of the stage's instructions. A few KiB a thread, not
/// 8 bytes a road vertex.
class LegLengths {
 public:
  LegLengths() : slots_(kSlots) {}

  /// Those of `piece` (index piece_index), computed when it is not kept.
  const std::vector<double>& of(std::size_t piece_index, const RoadPiece& piece) {
    Slot& slot = slots_[piece_index & (kSlots - 1)];
    if (slot.piece != piece_index) {
      slot.piece = piece_index;
      slot.legs.clear();
      for (std::size_t k = 0; k + 1 < piece.points.size(); ++k) {
        slot.legs.push_back(distance_m(piece.points[k], piece.points[k + 1]));
      }
    }
    return slot.legs;
  }

 private:
  static constexpr std::size_t kSlots = 256;
  struct Slot {
    std::size_t piece = std::numeric_limits<std::size_t>::max();
    std::vector<double> legs;
  };
  std::vector<Slot> slots_;
};

/// Cumulative length at each vertex of a piece.
inline std::vector<double> cumulative_m(const std::vector<PlanePoint>& points) {
  std::vector<double> out(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) {
    out[i] = out[i - 1] + distance_m(points[i - 1], points[i]);
  }
  return out;
}

/// Index of the leg [i, i+1] of the piece that holds position pos_m.
inline std::size_t leg_at(const std::vector<double>& cumulative, double pos_m) {
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), pos_m);
  const auto i = static_cast<std::size_t>(std::max<std::ptrdiff_t>(1, it - cumulative.begin()));
  return std::min(i, cumulative.size() - 1) - 1;
}

/// The first direction (unit vector) of a piece leaving the node it is incident at.
inline PlanePoint leaving_direction(const RoadPiece& piece, bool at_end) {
  const std::size_t n = piece.points.size();
  const PlanePoint& from = at_end ? piece.points[n - 1] : piece.points[0];
  for (std::size_t k = 1; k < n; ++k) {
    const PlanePoint& to = at_end ? piece.points[n - 1 - k] : piece.points[k];
    const double len = distance_m(from, to);
    if (len > 1e-9) return {(to.x - from.x) / len, (to.y - from.y) / len};
  }
  return {0.0, 0.0};
}

/// leaving_direction of every piece end, [piece][at_end], computed once (a path's every node
/// asked it of each piece there).
inline std::vector<std::array<PlanePoint, 2>> leaving_directions(const RoadGraph& graph) {
  std::vector<std::array<PlanePoint, 2>> out;
  out.reserve(graph.pieces.size());
  for (const RoadPiece& piece : graph.pieces) {
    out.push_back({leaving_direction(piece, false), leaving_direction(piece, true)});
  }
  return out;
}

/// The straightest continuation at `node` for a path arriving with direction `heading`
/// (unit), other than the piece end it arrived through; nullptr at a dead end. Ties go to the
/// lower piece index, so the choice is deterministic.
inline const Incidence* continuation(const std::vector<std::array<PlanePoint, 2>>& leaving,
                                     std::span<const Incidence> at_node, const Incidence& arrived,
                                     const PlanePoint& heading) {
  const Incidence* best = nullptr;
  double best_cos = -2.0;
  for (const Incidence& c : at_node) {
    if (c.piece == arrived.piece && c.at_end == arrived.at_end) continue;
    const PlanePoint d = leaving[c.piece][c.at_end ? 1 : 0];
    const double cos = d.x * heading.x + d.y * heading.y;
    if (cos > best_cos) best_cos = cos, best = &c;
  }
  return best;
}

inline PlanePoint last_heading(const Path& path) {
  const std::size_t n = path.points.size();
  if (n < 2) return {0.0, 0.0};
  const double len = distance_m(path.points[n - 2], path.points[n - 1]);
  return {(path.points[n - 1].x - path.points[n - 2].x) / len,
          (path.points[n - 1].y - path.points[n - 2].y) / len};
}

/// Where each piece end's node is in `incidences` ([piece][at_end], Incidences::index_of;
/// kNoNode for a node that is not a graph node), found once instead of at every hop of every
/// path.
inline constexpr std::uint32_t kNoNode = std::numeric_limits<std::uint32_t>::max();
inline std::vector<std::array<std::uint32_t, 2>> end_nodes(const RoadGraph& graph,
                                                           const Incidences& incidences) {
  if (incidences.node_count() >= kNoNode) {
    throw std::length_error("sight: more than 2^32 - 2 graph nodes");
  }
  const auto index = [&](std::int64_t node) {
    const std::size_t i = incidences.index_of(node);
    return i == Incidences::npos ? kNoNode : static_cast<std::uint32_t>(i);
  };
  std::vector<std::array<std::uint32_t, 2>> out;
  out.reserve(graph.pieces.size());
  for (const RoadPiece& piece : graph.pieces) {
    out.push_back({index(piece.from_node_id), index(piece.to_node_id)});
  }
  return out;
}

/// The road from position pos_m of a piece in one direction, continued through graph nodes onto
/// the straightest continuation, until it is range_m long or reaches a dead end; into a Path
/// (its buffers are reused from segment to segment), followed only as far as it is asked: most
/// views in a town end long before the range, and the road beyond them was followed for nothing.
/// Going on where it stopped adds the same points as one walk to the range: the same vertices in
/// the same order, each step's length the same hypot, each continuation chosen on the same
/// heading. A piece's vertices are taken up to the first at or beyond the range (no position,
/// outline or heading reads further).
class RoadFollower {
 public:
  /// nodes: end_nodes.
  RoadFollower(const RoadGraph& graph, const Incidences& incidences,
               const std::vector<std::array<std::uint32_t, 2>>& nodes,
               const std::vector<std::vector<double>>& cumulative,
               const std::vector<std::array<PlanePoint, 2>>& leaving, double range_m, Path& path,
               LegLengths& legs)
      : graph_(graph),
        incidences_(incidences),
        nodes_(nodes),
        cumulative_(cumulative),
        leaving_(leaving),
        range_m_(range_m),
        path_(path),
        legs_(legs) {}

  /// A new road: its first point at pos_m of `piece`, walking towards its end or its start.
  void start(std::size_t piece, double pos_m, bool towards_end) {
    const RoadPiece& first = graph_.pieces[piece];
    const std::vector<double>& c = cumulative_[piece];
    const std::size_t leg = leg_at(c, pos_m);
    path_.points.clear();
    path_.at_m.clear();
    path_.points.push_back(lerp(first.points[leg], first.points[leg + 1],
                                (pos_m - c[leg]) / std::max(1e-9, c[leg + 1] - c[leg])));
    path_.at_m.push_back(0.0);
    enter(piece, pos_m, towards_end);
    hops_ = 0;
    ended_ = false;
  }

  /// Follows the road on until the path is longer than limit_m, range_m long or at its end.
  void extend_beyond(double limit_m) {
    // The other direction's follower may have taken the slot of this one's piece since.
    if (!ended_) legs_on_ = legs_.of(arrived_.piece, graph_.pieces[arrived_.piece]).data();
    while (!ended_ && path_.length_m() < range_m_ && path_.length_m() <= limit_m) {
      if (remaining_ == 0) {
        hop();
        continue;
      }
      add_next_vertex();
    }
  }
  void extend_to_range() { extend_beyond(std::numeric_limits<double>::infinity()); }

  const Path& path() const { return path_; }

 private:
  /// The piece's next vertex onto the path. From the vertex before it on the piece (the path's
  /// last point, bit for bit) the step is that leg's length, distance_m of the same two points
  /// (walking backwards, of their differences' negatives: the same hypot).
  void add_next_vertex() {
    const PlanePoint* const points = points_on_;
    const std::size_t k = next_vertex_;
    const bool forward = arrived_.at_end;
    // The vertex before k on the piece: k > 0 walking forward (k starts at a leg's end), k is
    // below the last vertex walking backwards (it starts at a leg's start).
    const PlanePoint& before = points[forward ? k - 1 : k + 1];
    const PlanePoint& last = path_.points.back();
    if (last.x == before.x && last.y == before.y) {
      path_.add(points[k], legs_on_[forward ? k - 1 : k]);
    } else {
      path_.add(points[k]);
    }
    --remaining_;
    if (forward) {
      ++next_vertex_;
    } else if (remaining_ > 0) {
      --next_vertex_;
    }
  }

  /// The vertices of `piece` after position pos_m in the walking direction come next.
  void enter(std::size_t piece, double pos_m, bool towards_end) {
    const std::size_t leg = leg_at(cumulative_[piece], pos_m);
    points_on_ = graph_.pieces[piece].points.data();
    legs_on_ = legs_.of(piece, graph_.pieces[piece]).data();
    arrived_ = {piece, towards_end};
    next_vertex_ = towards_end ? leg + 1 : leg;
    remaining_ = towards_end ? graph_.pieces[piece].points.size() - (leg + 1) : leg + 1;
  }

  /// Onto the straightest continuation at the node the path has reached; ended at a dead end.
  /// A ring of pieces shorter than the range is walked round again; the bound stops a ring of
  /// zero-length pieces.
  void hop() {
    if (hops_ >= 10000) {
      ended_ = true;
      return;
    }
    ++hops_;
    const std::uint32_t node = nodes_[arrived_.piece][arrived_.at_end ? 1 : 0];
    const std::span<const Incidence> at_node =
        node == kNoNode ? std::span<const Incidence>() : incidences_.at_index(node);
    const Incidence* next = continuation(leaving_, at_node, arrived_, last_heading(path_));
    if (!next) {
      ended_ = true;
      return;
    }
    // Entering at its from-node walks it towards its end, and the other way round.
    const bool forward = !next->at_end;
    enter(next->piece, forward ? 0.0 : graph_.pieces[next->piece].length_m + 1.0, forward);
  }

  const RoadGraph& graph_;
  const Incidences& incidences_;
  const std::vector<std::array<std::uint32_t, 2>>& nodes_;
  const std::vector<std::vector<double>>& cumulative_;
  const std::vector<std::array<PlanePoint, 2>>& leaving_;
  const double range_m_;
  Path& path_;
  LegLengths& legs_;
  /// The points and leg lengths of the piece being walked (legs_on_: valid while this follower
  /// alone walks, so taken again by each extend_beyond).
  const PlanePoint* points_on_ = nullptr;
  const double* legs_on_ = nullptr;
  Incidence arrived_{};          ///< the piece being walked, and whether towards its end
  std::size_t next_vertex_ = 0;  ///< its vertex that comes next
  std::size_t remaining_ = 0;    ///< its vertices still to come
  std::size_t hops_ = 0;
  bool ended_ = false;
};

}  // namespace roadcross::preprocess::sight_detail
