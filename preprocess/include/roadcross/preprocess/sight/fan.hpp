// Fans of sight lines: the lines from one eye to consecutive vehicle positions, tested
// at once against the edge grid (edge_grid.hpp) — which edges may block any of them (the
// candidates, tested line by line) and whether a whole road direction is open to both kerbs.
// Internal to preprocess/src/sight/sight.cpp; a header so that the unit tests reach the pieces. As
// for the grid, every answer is the line-by-line test's, bit for bit: the proofs are in the
// comments.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "roadcross/preprocess/sight/edge_grid.hpp"

namespace roadcross::preprocess::sight_detail {

/// The convex hull of `points` into `hull` (counter-clockwise, from the lowest-x point;
/// duplicates dropped; `points` is sorted in place). Andrew's monotone chain, dropping a point
/// only when it is certainly inside: the turn's cross product is below minus a bound on its
/// rounding error. A nearly collinear point stays as a vertex, so the polygon may bend inwards
/// by ~1e-14 of its size, but every input point lies in the hull of the vertices returned,
/// which is what the fan test relies on.
inline void convex_hull(std::vector<PlanePoint>& points, std::vector<PlanePoint>& hull) {
  const auto before = [](const PlanePoint& p, const PlanePoint& q) {
    return p.x < q.x || (p.x == q.x && p.y < q.y);
  };
  // A chunk's few points (its eyes and a straight road's ends) sort faster by insertion.
  if (points.size() <= 16) {
    for (std::size_t i = 1; i < points.size(); ++i) {
      const PlanePoint p = points[i];
      std::size_t j = i;
      for (; j > 0 && before(p, points[j - 1]); --j) points[j] = points[j - 1];
      points[j] = p;
    }
  } else {
    std::sort(points.begin(), points.end(), before);
  }
  points.erase(std::unique(points.begin(), points.end(),
                           [](const PlanePoint& p, const PlanePoint& q) {
                             return p.x == q.x && p.y == q.y;
                           }),
               points.end());
  hull.clear();
  if (points.size() < 3) {
    hull.assign(points.begin(), points.end());
    return;
  }
  // (b - a) x (c - a) < 0 for certain: the computed value is within 4.1 u (|t1| + |t2|) of the
  // true one (u = 2^-53; differences and products each rounded once), 8 u is the bound used.
  const auto certainly_right_turn = [](const PlanePoint& a, const PlanePoint& b,
                                       const PlanePoint& c) {
    const double t1 = (b.x - a.x) * (c.y - a.y), t2 = (b.y - a.y) * (c.x - a.x);
    constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
    return t1 - t2 < -8 * kU * (std::abs(t1) + std::abs(t2));
  };
  for (const PlanePoint& p : points) {  // the lower chain, left to right
    while (hull.size() >= 2 && certainly_right_turn(hull[hull.size() - 2], hull.back(), p))
      hull.pop_back();
    hull.push_back(p);
  }
  const std::size_t lower = hull.size();
  for (std::size_t i = points.size() - 1; i-- > 0;) {  // the upper chain, right to left
    while (hull.size() > lower &&
           certainly_right_turn(hull[hull.size() - 2], hull.back(), points[i]))
      hull.pop_back();
    hull.push_back(points[i]);
  }
  hull.pop_back();  // the first point again
}

/// The same, returned (for the tests).
inline std::vector<PlanePoint> convex_hull(std::vector<PlanePoint> points) {
  std::vector<PlanePoint> hull;
  convex_hull(points, hull);
  return hull;
}

/// A fan of sight lines from one eye to consecutive targets, and the test that lets the sight
/// stage skip them all: an obstacle edge that is clear of the fan cannot block any of its
/// lines, because crossing_parameter returns NaN for it with every one of them.
///
/// Why (u = 2^-53, |v|1 = |vx| + |vy|; r = target - eye, s = b - a, q = a - eye, D = r x s):
/// crossing_parameter computes D, q x s and q x r each within 4.1 u of |r|1|s|1, |q|1|s|1,
/// |q|1|r|1 and answers only when both quotients round into [0, 1], i.e. for the reals
/// lambda = (q x s)'/D', mu = (q x r)'/D' in [0, 1 + u]. Then w = (eye + lambda r) -
/// (a + mu s) has |w x s| <= 4.2 u |s|1 (|r|1 + |q|1) and |w x r| <= 4.2 u |r|1 (|s|1 + |q|1),
/// and from w D = (w x s) r - (w x r) s, |w| |D| <= 4.2 u |r|1 |s|1 M with M = |r|1 + |s|1 +
/// 2 |q|1. The two points are on the line and on the edge (to u of their lengths), so if the
/// edge is kMarginM from every line (edge_clear asks kGapM from the hull of the eye and the
/// outline, which holds them all), |w| >= 0.8 kMarginM and so |D| <= 5.3 u |r|1 |s|1 M / kMarginM:
/// the edge would have to be parallel to the line to 1e-9, and then |q x s| = |lambda D - w x s| <=
/// u |s|1 M (5.4 |r|1 / kMarginM + 4.2) - the eye within ~1e-6 m of the edge's own line. edge_clear
/// asks for both: kMarginM of separation (by separating axes: the hull's edge normals, x, y and the
/// edge's normal) and |q x s| above 8 u |s|1 M (R1 / kMarginM + 2), R1 the largest |r|1 of the fan.
/// It is conservative: a false answer only makes the edge a candidate (fan_candidates).
class Fan {
 public:
  /// Far above the rounding of coordinates (~1e-9 m at UTM's 1e7 m) and of the projections
  /// below (~1e-12 m), far below anything that matters to a wall: 1 mm.
  static constexpr double kMarginM = 1e-3;
  /// How far outside the hull of the eye and the outline a target may lie.
  static constexpr double kOutlineSlackM = 1e-7;

  /// The fan from `eye` to targets that lie in the hull of `eye` and `outline` (at least one
  /// point), or within kOutlineSlackM of it. Allocates only while the buffers grow.
  void reset(const PlanePoint& eye, const std::vector<PlanePoint>& outline) {
    set_eye_and_reach(eye, outline);
    points_.assign(outline.begin(), outline.end());
    points_.push_back(eye);
    if (!triangle(eye, outline)) convex_hull(points_, hull_);
    set_axes();
  }

  /// reset(eye, outline) for the points `other` was reset with (its eye and outline, in any
  /// order and split; the same answers): their hull is other's, not computed again.
  void reset_sharing_hull(const Fan& other, const PlanePoint& eye,
                          const std::vector<PlanePoint>& outline) {
    set_eye_and_reach(eye, outline);
    hull_ = other.hull_;
    set_axes();
  }

  /// The hull of the eye and the outline (for EdgeGrid::any_in_polygon).
  const std::vector<PlanePoint>& hull() const { return hull_; }
  const PlanePoint& eye() const { return eye_; }

 private:
  void set_eye_and_reach(const PlanePoint& eye, const std::vector<PlanePoint>& outline) {
    eye_ = eye;
    reach_m_ = 0.0;  // |t - eye|1 is convex: its largest over the hull is at a vertex
    for (const PlanePoint& t : outline) {
      reach_m_ = std::max(reach_m_, std::abs(t.x - eye.x) + std::abs(t.y - eye.y));
    }
    reach_m_ += 2 * kOutlineSlackM;
    constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
    near_ = reach_m_ < kFarM;
    cross_bound_ = 8 * kU * (reach_m_ / kMarginM + 2);
  }

  void set_axes() {
    const PlanePoint eye = eye_;
    rel_hull_.clear();
    for (const PlanePoint& v : hull_) rel_hull_.push_back({v.x - eye.x, v.y - eye.y});
    // Axes x, y and the hull's edge normals (not unit: a gap is asked for as kGapM |n|1 >=
    // kGapM |n|), with the bounds every point keeps along each, relative to the eye, widened by
    // the gap: those of the hull's vertices (every point is in their hull; a projection's
    // rounding, < 1e-10 m, is inside kGapM's 1e-6 m), fewer than the points on a winding road.
    // The long sides first: a fan along a road is a thin wedge, and most edges near it lie
    // beside one of its two long sides. An axis's bounds are computed when an edge first needs
    // them (Axis::bound): most edges are told apart by the first one or two, and a winding
    // road's hull has dozens of sides.
    axes_.clear();
    for (std::size_t i = 0; i < hull_.size() && hull_.size() > 1; ++i) {
      const PlanePoint& a = hull_[i];
      const PlanePoint& b = hull_[i + 1 < hull_.size() ? i + 1 : 0];
      const PlanePoint n{-(b.y - a.y), b.x - a.x};
      if (n.x != 0.0 || n.y != 0.0) axes_.push_back(Axis{n, std::abs(n.x) + std::abs(n.y)});
    }
    // The two longest to the front (a wedge's two long sides; the order of the rest does not
    // matter, nor does any order change an answer: an edge is separated when any axis separates
    // it).
    for (std::size_t front = 0; front < 2 && front + 1 < axes_.size(); ++front) {
      std::size_t longest = front;
      for (std::size_t i = front + 1; i < axes_.size(); ++i) {
        if (axes_[i].size > axes_[longest].size) longest = i;
      }
      if (longest != front) std::swap(axes_[front], axes_[longest]);
    }
    axes_.push_back(Axis{{1.0, 0.0}, 1.0});
    axes_.push_back(Axis{{0.0, 1.0}, 1.0});
  }

 public:
  /// True only when no line of the fan can be crossed by the edge a->b (see the class).
  bool edge_clear(const PlanePoint& a, const PlanePoint& b) const {
    const PlanePoint ra{a.x - eye_.x, a.y - eye_.y}, rb{b.x - eye_.x, b.y - eye_.y};
    return eye_clear(ra, rb, {b.x - a.x, b.y - a.y}) && separated(ra, rb);
  }

  /// True only when the edge a->b is at least kMarginM from every point of the hull: the
  /// separating axes of edge_clear alone (with its bound on the distances), without the eye's
  /// own test that crossing_parameter's rounding needs. Enough where no crossing_parameter is
  /// computed (the shadows on flat ground, sight.cpp).
  bool edge_apart(const PlanePoint& a, const PlanePoint& b) const {
    if (!near_) return false;
    const PlanePoint ra{a.x - eye_.x, a.y - eye_.y}, rb{b.x - eye_.x, b.y - eye_.y};
    if (!(std::abs(ra.x) + std::abs(ra.y) < kFarM && std::abs(rb.x) + std::abs(rb.y) < kFarM)) {
      return false;
    }
    return separated(ra, rb);
  }

  /// True when edge_apart's reach tests (near_, both ends within kFarM of the eye) pass for
  /// every edge EdgeGrid::any_in_polygon offers for hull() on a grid whose longest edge (|.|1)
  /// is longest_edge_m and whose cells are cell_m: then edge_apart(a, b) is separated_from(a,
  /// b). Why: an offered edge is filed in a visited cell, so it passes within 1e-6 of a cell of
  /// that cell; a visited cell lies within one cell and the margin of a point of the hull in x
  /// and in y (its row's strip holds hull points at every x of the row's extent), and every
  /// point of the hull is within reach_m_ of the eye (|.|1, largest at a vertex: the eye or a
  /// point of the outline). So both ends of the edge are within reach_m_ + 2 cells (32 m and a
  /// hair) + longest_edge_m of the eye (|.|1); 4 cells and half of kFarM leave the rounding of
  /// the ends' differences from the eye (~1e-9 m) far behind.
  bool reaches_all_of(double longest_edge_m, double cell_m) const {
    return near_ && reach_m_ + 4 * cell_m + longest_edge_m < kFarM / 2;
  }
  /// edge_apart(a, b) without its reach tests, for an edge reaches_all_of vouches for.
  bool separated_from(const PlanePoint& a, const PlanePoint& b) const {
    return separated({a.x - eye_.x, a.y - eye_.y}, {b.x - eye_.x, b.y - eye_.y});
  }

 private:
  /// The part of edge_clear that depends on the eye (ra, rb: the edge's ends relative to it):
  /// both ends and the targets within reach of the proof's bounds, and |q x s| above its bound
  /// (the eye off the edge's line; cross_bound_ holds its factors of the fan).
  bool eye_clear(const PlanePoint& ra, const PlanePoint& rb, const PlanePoint& s) const {
    const double qa = std::abs(ra.x) + std::abs(ra.y), qb = std::abs(rb.x) + std::abs(rb.y);
    if (!(qa < kFarM && qb < kFarM && near_)) return false;
    const double sx = s.x, sy = s.y;
    const double s1 = std::abs(sx) + std::abs(sy);
    const double m = reach_m_ + s1 + 2 * qa;
    const double cross = ra.x * sy - ra.y * sx;  // q x s
    return std::abs(cross) > cross_bound_ * s1 * m;
  }

  /// Beyond this (metres, |.|1 from the eye) the proof's bounds are not claimed.
  static constexpr double kFarM = 1e5;

  /// Projections of points within 1e5 m of the eye are off by < 1e-10 m, the targets may be
  /// kOutlineSlackM outside: 1e-6 m covers both.
  static constexpr double kGapM = kMarginM + 1e-6;

  /// The hull when it is the triangle of the eye and two targets that certainly turn (the
  /// fan along a straight road): no sorting. False: leave it to convex_hull.
  bool triangle(const PlanePoint& eye, const std::vector<PlanePoint>& outline) {
    if (outline.size() != 2) return false;
    const PlanePoint &b = outline[0], &c = outline[1];
    const double t1 = (b.x - eye.x) * (c.y - eye.y), t2 = (b.y - eye.y) * (c.x - eye.x);
    constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
    const double bound = 8 * kU * (std::abs(t1) + std::abs(t2));  // as in convex_hull
    hull_.clear();
    if (t1 - t2 > bound) {
      hull_.insert(hull_.end(), {eye, b, c});  // counter-clockwise
    } else if (t1 - t2 < -bound) {
      hull_.insert(hull_.end(), {eye, c, b});
    }
    return !hull_.empty();
  }

  struct Axis {
    PlanePoint n;       ///< the direction
    double size = 0.0;  ///< |n|1
    /// A segment entirely outside these is separated; set by bound() (NaN: not yet).
    double below = NAN, above = NAN;

    /// The hull's bounds along n widened by the gap, computed the first time they are asked.
    void bound(const std::vector<PlanePoint>& rel_hull) {
      if (!std::isnan(below)) return;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const PlanePoint& v : rel_hull) {
        const double d = n.x * v.x + n.y * v.y;
        lo = std::min(lo, d), hi = std::max(hi, d);
      }
      const double gap = kGapM * size;
      below = lo - gap, above = hi + gap;
    }
  };

  /// A separating axis with a gap of kGapM between the fan's points and the segment ra->rb
  /// (both relative to the eye).
  bool separated(const PlanePoint& ra, const PlanePoint& rb) const {
    for (Axis& axis : axes_) {
      axis.bound(rel_hull_);
      const double pa = axis.n.x * ra.x + axis.n.y * ra.y;
      const double pb = axis.n.x * rb.x + axis.n.y * rb.y;
      if (std::min(pa, pb) >= axis.above || std::max(pa, pb) <= axis.below) return true;
    }
    // The edge's own normal against the hull's vertices (every point is in their hull): all of
    // them at least the gap below the edge's projection, or all above it. Vertex by vertex,
    // stopping once neither can hold: the same answer as comparing with the vertices' largest
    // and smallest projections widened by the gap (rounding is monotonic: fl(max d + g) =
    // max fl(d + g)).
    const PlanePoint n{-(rb.y - ra.y), rb.x - ra.x};
    const double n1 = std::abs(n.x) + std::abs(n.y);
    if (!(n1 > 0.0)) return false;
    const double pa = n.x * ra.x + n.y * ra.y, pb = n.x * rb.x + n.y * rb.y;
    const double p_lo = std::min(pa, pb), p_hi = std::max(pa, pb), gap = kGapM * n1;
    bool below = true, above = true;
    for (const PlanePoint& v : rel_hull_) {
      const double d = n.x * v.x + n.y * v.y;
      below = below && p_lo >= d + gap;
      above = above && p_hi <= d - gap;
      if (!below && !above) return false;
    }
    return below || above;
  }

  PlanePoint eye_;
  double reach_m_ = 0.0;            ///< R1: the largest |target - eye|1
  bool near_ = false;               ///< reach_m_ < kFarM
  double cross_bound_ = 0.0;        ///< 8 u (R1 / kMarginM + 2): |q x s| must exceed it |s|1 M
  std::vector<PlanePoint> points_;  ///< the targets and the eye (sorted by the hull)
  std::vector<PlanePoint> hull_, rel_hull_;
  mutable std::vector<Axis> axes_;  ///< their bounds filled in by separated() as needed
};

/// An edge that may block a line of a fan: its id and its ends (read once per fan, not per
/// line), and the terms of crossing_parameter that depend only on the edge and the fan's eye
/// (computed once per fan: each line then computes only its own, the same arithmetic).
struct CandidateEdge {
  PlanePoint a, b;
  std::uint32_t id = 0;
  EdgeFromEye from_eye;
};

/// The obstacle edges that may block a line of `fan` (from its eye to a target Fan::reset
/// allows), into `out`: those that EdgeGrid::any_in_polygon offers for the fan's hull and
/// Fan::edge_clear does not clear. ends(i) gives edge i's ends as a pair of PlanePoints. Mostly
/// each once (an edge in several cells is judged once; the last id seen at each of 64 slots is
/// remembered), sometimes twice, which blocked_among does not mind.
///
/// Why every edge that matters is among them: for a line L of the fan (eye -> target t, t
/// within Fan::kOutlineSlackM of the hull), an edge i that any_along(L) offers and that can
/// block L has crossing_parameter(L, a_i, b_i) not NaN (see blocked_among), so edge_clear
/// is false for it (the Fan's proof); and any_along(L) offers only edges filed in cells
/// for_cells_along(eye, t) visits, which any_in_polygon(hull, kMarginM) visits too: L lies in
/// the hull widened by 1e-7 m, far inside the 1 mm margin, and any_in_polygon's rows and
/// columns cover the hull widened by the margin and for_cells_along's slack. So i is offered
/// here, and kept (an offer skipped by the 64 slots is an id judged before).
template <typename Ends>
void fan_candidates(const EdgeGrid& grid, const Fan& fan, Ends&& ends,
                    std::vector<CandidateEdge>& out) {
  out.clear();
  std::array<std::uint32_t, 64> judged;
  judged.fill(std::numeric_limits<std::uint32_t>::max());
  grid.any_in_polygon(fan.hull(), Fan::kMarginM, [&](std::uint32_t i) {
    std::uint32_t& slot = judged[i & 63];
    if (slot == i) return false;
    slot = i;
    const auto [a, b] = ends(i);
    if (!fan.edge_clear(a, b)) out.push_back({a, b, i, edge_from_eye(fan.eye(), a, b)});
    return false;  // every cell: all the candidates are wanted
  });
}

/// True only when no obstacle edge can block a line from either eye, `left` or `right`, to a
/// point in the hull of both eyes and `outline` (to Fan::kOutlineSlackM): every edge
/// EdgeGrid::any_in_polygon offers for that hull is cleared by both fans, from_left (reset from
/// `left` over `outline` and `right`) and from_right (from `right` over `outline` and `left`).
/// `outline` is left with one more point. ends(i) as for fan_candidates.
///
/// Why: the two fans hold the same points, so the same hull, and a line from either eye to a
/// point of it lies in it: the cells its walk visits are among those any_in_polygon visits
/// (fan_candidates' argument), and an edge both fans clear can be crossed by no line from
/// either eye (the Fan's proof, once per eye: it asks the eye not to lie near the edge's own
/// line, which is why one fan is not enough).
template <typename Ends>
bool open_to_both(const EdgeGrid& grid, Fan& from_left, Fan& from_right, const PlanePoint& left,
                  const PlanePoint& right, std::vector<PlanePoint>& outline, Ends&& ends) {
  outline.push_back(right);
  from_left.reset(left, outline);
  outline.back() = left;
  from_right.reset_sharing_hull(from_left, right, outline);
  std::array<std::uint32_t, 64> judged;  // as fan_candidates: most edges judged once
  judged.fill(std::numeric_limits<std::uint32_t>::max());
  return !grid.any_in_polygon(from_left.hull(), Fan::kMarginM, [&](std::uint32_t i) {
    std::uint32_t& slot = judged[i & 63];
    if (slot == i) return false;
    slot = i;
    const auto [a, b] = ends(i);
    return !from_left.edge_clear(a, b) || !from_right.edge_clear(a, b);
  });
}

/// True when an edge any_along(eye, target, ...) offers has blocks(candidate) true: the same
/// answer as EdgeGrid::any_along(eye, target, blocks of the id), given `candidates` from
/// fan_candidates for a fan from `eye` that allows `target`, and a `blocks` that is false
/// whenever crossing_parameter(PlanLine(eye, target), a, b) is NaN (an edge the line does not
/// cross in plan cannot block it).
///
/// Why the same: any_along's answer is whether some edge it offers (an edge filed in a cell the
/// line's walk visits) has blocks true. Such an edge is a candidate (fan_candidates). A
/// candidate with blocks true counts only if it is one of them: the grid files edge i in the
/// cells of for_cells_along(a_i, b_i), and CellsAlong::visits says with the walk's own
/// arithmetic whether the line visits one of those. (crossing_parameter alone is not enough:
/// an edge nearly collinear with the line, beyond its end, can round to a crossing; the line's
/// walk would never offer it.) The check walks the edge's few cells, and only for an edge
/// that blocks.
template <typename Blocks>
bool blocked_among(const std::vector<CandidateEdge>& candidates, const PlanePoint& eye,
                   const PlanePoint& target, Blocks&& blocks) {
  for (const CandidateEdge& c : candidates) {
    if (!blocks(c)) continue;
    const CellsAlong line(eye, target, EdgeGrid::kCellM);
    if (for_cells_along(c.a, c.b, EdgeGrid::kCellM, [&](std::int64_t col, std::int64_t row) {
          return line.visits(col, row);
        })) {
      return true;
    }
  }
  return false;
}

}  // namespace roadcross::preprocess::sight_detail
