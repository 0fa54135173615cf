// Shadows on the road: which stretch of one straight leg of the road an obstacle edge hides from
// an eye, in closed form. On flat ground (no terrain) a line of sight from the eye to the vehicle
// at a point P of the leg is blocked by the edge a->b when it crosses the edge where the line's
// height lies in the edge's opaque band; the height grows linearly along the line (sensor to
// object height), so "the band" is a range of the fraction along the line. The points of the leg
// whose line is blocked form one interval (the central projection from the eye of the part of
// the edge inside the region those crossings may lie in, which is convex): the shadow. Internal to
// preprocess/src/sight/sight.cpp; a header so that the unit tests reach it.
#pragma once

#include <algorithm>
#include <cmath>

#include "roadcross/preprocess/sight/obstacle_edge.hpp"

namespace roadcross::preprocess::sight_detail {

/// The fractions [from, to] along a line of sight (0 at the eye, 1 at the vehicle) where an
/// edge with the opaque band [bottom_m, top_m] above the ground blocks it, on flat ground with
/// the line rising from eye_height_m to object_height_m (both >= 0, metres); empty (from > to)
/// when the band is wholly above or below the line.
struct BlockingFractions {
  double from = 0.0, to = 1.0;
  bool empty() const { return !(from <= to); }
};

inline BlockingFractions blocking_fractions(double bottom_m, double top_m, double eye_height_m,
                                            double object_height_m) {
  const double rise_m = object_height_m - eye_height_m;
  if (rise_m == 0.0) {
    const bool inside = bottom_m <= eye_height_m && eye_height_m <= top_m;
    return inside ? BlockingFractions{0.0, 1.0} : BlockingFractions{1.0, 0.0};
  }
  double at_bottom = (bottom_m - eye_height_m) / rise_m, at_top = (top_m - eye_height_m) / rise_m;
  if (at_bottom > at_top) std::swap(at_bottom, at_top);
  return {std::max(0.0, at_bottom), std::min(1.0, at_top)};
}

/// The interval [from, to] of the leg's parameter u in [0, 1] (P(u) = p0 + u (p1 - p0)) whose
/// lines of sight from `eye` the edge a->b blocks at a fraction in `fractions`; empty when none.
struct LegShadow {
  double from = 1.0, to = 0.0;
  bool empty() const { return !(from <= to); }
};

/// The shadow on a leg in line with the eye (e0, e1: its ends relative to the eye, their cross
/// product nearly 0; a, b: the edge's ends relative to the eye): every line of sight runs along
/// the ray to the farther end, and an edge crossing that ray at distance r from the eye hides the
/// points of the leg farther than r. (The band's fractions are not applied: such a leg points
/// straight at the kerb, or starts at the eye when the carriageway has no width.)
inline LegShadow in_line_shadow(double e0x, double e0y, double e1x, double e1y, double ax,
                                double ay, double bx, double by) {
  const double r0 = std::hypot(e0x, e0y), r1 = std::hypot(e1x, e1y);
  const double fx = r1 >= r0 ? e1x : e0x, fy = r1 >= r0 ? e1y : e0y;  // the farther end
  // eye + lambda f = a + mu (b - a), lambda and mu in [0, 1].
  const double sx = bx - ax, sy = by - ay;
  const double denom = fx * sy - fy * sx;
  if (denom == 0.0) return {};
  const double lambda = (ax * sy - ay * sx) / denom, mu = (ax * fy - ay * fx) / denom;
  if (lambda < 0.0 || lambda > 1.0 || mu < 0.0 || mu > 1.0) return {};
  const double hidden_from_m = lambda * std::max(r0, r1);
  if (r1 == r0) return hidden_from_m <= r0 ? LegShadow{0.0, 1.0} : LegShadow{};
  const double u = (hidden_from_m - r0) / (r1 - r0);
  if (r1 > r0) return u <= 1.0 ? LegShadow{std::max(0.0, u), 1.0} : LegShadow{};
  return u >= 0.0 ? LegShadow{0.0, std::min(1.0, u)} : LegShadow{};
}

/// Why it is one interval: the crossings that count lie in the region R = {E + t (P(u) - E) :
/// u in [0, 1], t in fractions}, the leg's triangle with the eye cut by the two lines parallel to
/// the leg at those fractions: an intersection of half-planes, convex. The edge's part inside R
/// is one segment, and the central projection from the eye maps it monotonically onto the leg.
/// With x the 2D cross product and D = (p0 - E) x (p1 - E), a point X is in the wedge when
/// (p0 - E) x (X - E) and (X - E) x (p1 - E) have D's sign; it lies at the fraction
/// t(X) = ((X - E) x (p1 - p0)) / D of the line through it, and that line ends at
/// u(X) = ((X - E) x (p0 - E)) / ((p1 - p0) x (X - E)). The only point of R on a line through the
/// eye parallel to the leg is the eye itself (t = 0): an edge through the eye hides the whole
/// leg (a line crossing an edge at its very start is blocked, as in the line-by-line test).
/// (It and its seen_at are inlined by force into the sight stage's one caller, called per
/// candidate edge and leg: GCC's heuristics left them out of line as sight.cpp grew, +0.2 G
/// instructions on 10x tiled Monaco.)
ROADCROSS_INLINE inline LegShadow leg_shadow(const PlanePoint& eye, const PlanePoint& p0,
                                             const PlanePoint& p1, const PlanePoint& a,
                                             const PlanePoint& b,
                                             const BlockingFractions& fractions) {
  if (fractions.empty()) return {};
  const double e0x = p0.x - eye.x, e0y = p0.y - eye.y, e1x = p1.x - eye.x, e1y = p1.y - eye.y;
  const double vx = p1.x - p0.x, vy = p1.y - p0.y;
  const double ax = a.x - eye.x, ay = a.y - eye.y, bx = b.x - eye.x, by = b.y - eye.y;
  // An edge through the eye itself is crossed by every line at its start (fraction 0).
  if (ax * by - ay * bx == 0.0 && ax * bx + ay * by <= 0.0) {
    return fractions.from == 0.0 ? LegShadow{0.0, 1.0} : LegShadow{};
  }
  const double d = e0x * e1y - e0y * e1x;
  const double scale = (std::abs(e0x) + std::abs(e0y)) * (std::abs(vx) + std::abs(vy));
  if (!(std::abs(d) > 1e-12 * scale)) return in_line_shadow(e0x, e0y, e1x, e1y, ax, ay, bx, by);
  // Clip the edge X(s) = a + s (b - a), s in [0, 1], to R: each constraint f(X) >= 0 is linear.
  // An end cut by one of the wedge's sides lies on the line to p0 or p1: it is seen at u = 0 or
  // 1 exactly (computing u there would round, and a position at a leg's end, as every chunk's
  // last, could fall just outside a shadow that covers it).
  enum Cut { kNone, kSide0, kSide1 };
  double s0 = 0.0, s1 = 1.0;
  Cut cut0 = kNone, cut1 = kNone;
  const auto clip = [&](double fa, double fb, Cut cut) {
    if (fa < 0.0 && fb < 0.0) return false;
    if (fa < 0.0) {
      const double s = fa / (fa - fb);
      if (s > s0) s0 = s, cut0 = cut;
    }
    if (fb < 0.0) {
      const double s = fa / (fa - fb);
      if (s < s1) s1 = s, cut1 = cut;
    }
    return s0 <= s1;
  };
  const double sign = d > 0.0 ? 1.0 : -1.0;
  if (!clip(sign * (e0x * ay - e0y * ax), sign * (e0x * by - e0y * bx), kSide0)) return {};
  if (!clip(sign * (ax * e1y - ay * e1x), sign * (bx * e1y - by * e1x), kSide1)) return {};
  const double ta = (ax * vy - ay * vx) / d, tb = (bx * vy - by * vx) / d;
  if (!clip(ta - fractions.from, tb - fractions.from, kNone)) return {};
  if (!clip(fractions.to - ta, fractions.to - tb, kNone)) return {};
  bool at_eye = false;
  const auto seen_at = [&](double s, Cut cut) ROADCROSS_INLINE {
    if (cut != kNone) return cut == kSide0 ? 0.0 : 1.0;
    const double wx = ax + s * (bx - ax), wy = ay + s * (by - ay);
    const double denom = vx * wy - vy * wx;
    if (!(std::abs(denom) > 1e-12 * scale)) {
      at_eye = true;
      return 0.0;
    }
    return std::clamp((wx * e0y - wy * e0x) / denom, 0.0, 1.0);
  };
  const double u0 = seen_at(s0, cut0), u1 = seen_at(s1, cut1);
  if (at_eye) return {0.0, 1.0};
  return {std::min(u0, u1), std::max(u0, u1)};
}

}  // namespace roadcross::preprocess::sight_detail
