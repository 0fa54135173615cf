// The sight stage's spatial index of obstacle edges and its line-edge crossing test (issue 11;
// made faster for issue 8). Internal to preprocess/src/sight.cpp; a header so that the unit
// tests reach the pieces. Every change here must leave the stage's answers bit for bit as they
// were: the cells a line visits, the edges filed in them and the crossing arithmetic are the
// same as before; only the memory layout and cheap certain rejects are new.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "roadcross/preprocess/obstacle_edge.hpp"

#if defined(__GNUC__)
#define ROADCROSS_INLINE __attribute__((always_inline))
#else
#define ROADCROSS_INLINE
#endif

namespace roadcross::preprocess::sight_detail {

/// floor(x) as an integer, for |x| < 2^62 (cell coordinates): the same value as
/// static_cast<std::int64_t>(std::floor(x)) without the libm call.
inline std::int64_t floor_to_int(double x) {
  const auto t = static_cast<std::int64_t>(x);  // truncates towards zero
  return static_cast<double>(t) > x ? t - 1 : t;
}

/// The square cells of side `cell_m` that the segment a->b passes through, as for_cells_along
/// visits them: rows first_row..last_row (upwards or downwards), in each row the columns
/// columns() gives. Row by row: the part of the segment inside each row of cells gives the
/// columns. Every interval is widened by kSlack cells, so a point of the segment is always in a
/// visited cell despite rounding (and so is every point within ~kSlack cells of it). visits()
/// answers for one cell with the walk's own arithmetic (the fans' candidate edges ask whether
/// an edge is filed in a cell a line visits; see fan_candidates).
struct CellsAlong {
  static constexpr double kSlack = 1e-6;  // in cells: 16 micrometres at 16 m
  double ax, ay, bx, by;                  ///< the ends, in cells
  bool up, right;                         ///< the walk's directions
  std::int64_t first_row, last_row;

  CellsAlong(const PlanePoint& a, const PlanePoint& b, double cell_m)
      : ax(a.x / cell_m),
        ay(a.y / cell_m),
        bx(b.x / cell_m),
        by(b.y / cell_m),
        up(by >= ay),
        right(bx >= ax) {
    const double y_min = std::min(ay, by), y_max = std::max(ay, by);
    first_row = floor_to_int((up ? y_min : y_max) + (up ? -kSlack : kSlack));
    last_row = floor_to_int((up ? y_max : y_min) + (up ? kSlack : -kSlack));
  }

  /// The columns c0..c1 of row `row` (one of the rows above).
  void columns(std::int64_t row, std::int64_t& c0, std::int64_t& c1) const {
    double x0 = std::min(ax, bx), x1 = std::max(ax, bx);
    if (by != ay) {
      // The segment's x at the row's lower and upper edges, clamped to the segment.
      const double t0 = std::clamp((double(row) - kSlack - ay) / (by - ay), 0.0, 1.0);
      const double t1 = std::clamp((double(row + 1) + kSlack - ay) / (by - ay), 0.0, 1.0);
      x0 = ax + t0 * (bx - ax);
      x1 = ax + t1 * (bx - ax);
      if (x0 > x1) std::swap(x0, x1);
    }
    c0 = floor_to_int(x0 - kSlack);
    c1 = floor_to_int(x1 + kSlack);
  }

  /// True when the walk visits cell (column, row).
  bool visits(std::int64_t column, std::int64_t row) const {
    if (up ? (row < first_row || row > last_row) : (row > first_row || row < last_row)) {
      return false;
    }
    std::int64_t c0 = 0, c1 = 0;
    columns(row, c0, c1);
    return c0 <= column && column <= c1;
  }
};

/// Calls visit(ix, iy) for every cell of CellsAlong(a, b, cell_m), starting at a's end, until
/// visit returns true (then returns true).
/// (Multiplying by the reciprocal of the height instead of the two divisions per row, with the
/// divisions only near cell boundaries, gave the same cells but no measurable gain.)
template <typename Visit>
bool for_cells_along(const PlanePoint& a, const PlanePoint& b, double cell_m, Visit&& visit) {
  const CellsAlong cells(a, b, cell_m);
  const std::int64_t row_step = cells.up ? 1 : -1;
  for (std::int64_t row = cells.first_row;; row += row_step) {
    std::int64_t c0 = 0, c1 = 0;
    cells.columns(row, c0, c1);
    if (cells.right) {
      for (std::int64_t c = c0; c <= c1; ++c) {
        if (visit(c, row)) return true;
      }
    } else {
      for (std::int64_t c = c1; c >= c0; --c) {
        if (visit(c, row)) return true;
      }
    }
    if (row == cells.last_row) return false;
  }
}

/// Obstacle edges bucketed by the square cells they pass through. The cells are grouped in
/// tiles of 16 x 16; the occupied tiles are in a small open-addressing hash table (a country's
/// extent would not fit a dense array), and each tile has a dense table of where its cells'
/// edge lists begin. A line of sight looks up a tile only when it enters one (2-3 lookups on
/// 300 m instead of one per cell, each a random access into a table of the whole map), and a
/// row of a tile's cells is one cache line. A line visits its cells from the eye outwards and stops
/// at the first edge that blocks it: most blocked lines stop near the eye, and a clear line looks
/// only at the edges along it. (An R*-tree queried with the line cost 4x as much: it walks the
/// whole query and tests every node box against the line.)
///
/// Memory: 4 bytes per (edge, cell), 1 KiB per occupied tile (4 bytes per cell) and 32-64
/// bytes per tile in the hash table. A dense city fills most cells of its tiles (10x Monaco's
/// peak fell from 250 to 231 MiB against a hashed table of cells, 48-96 bytes per occupied
/// cell); a lone farm pays 1 KiB for its tile.
class EdgeGrid {
 public:
  /// 8-16 m were equally fast on Monaco; 6 and 24 m slower.
  static constexpr double kCellM = 16.0;
  static constexpr int kTileShift = 4;  ///< 2^4 = 16 cells a tile side
  static constexpr std::int64_t kTileSide = std::int64_t{1} << kTileShift;
  static constexpr std::size_t kTileCells = std::size_t{1} << (2 * kTileShift);

  /// Two walks over the edges' cells: the first counts the edges of each cell, the second files
  /// them (every cell's edges in increasing index order). The edges' indices are their
  /// positions in the vector.
  explicit EdgeGrid(const std::vector<ObstacleEdge>& edges) {
    build(edges.size(), [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
      a = edges[i].a, b = edges[i].b;
      return true;
    });
  }
  /// The same with the edges' ids in the store (its slots that are no edge are skipped).
  explicit EdgeGrid(const ObstacleEdges& edges) {
    build(edges.slots(), [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
      if (!edges.is_edge(i)) return false;
      a = edges.a(static_cast<std::uint32_t>(i)), b = edges.b(static_cast<std::uint32_t>(i));
      return true;
    });
  }

  /// True when test(edge index) is true for an edge in a cell the segment a->b passes through
  /// (every edge the segment crosses is among them); the cells are visited from a. An edge
  /// listed in two cells along the line is offered twice (remembering the edges offered cost
  /// more than the 12 % of repeated tests it saved on Monaco).
  /// (The sight stage now tests each line against its fan's candidates, blocked_among; this
  /// line-by-line walk gives the answer it must equal, and is the tests' reference.)
  template <typename Test>
  bool any_along(const PlanePoint& a, const PlanePoint& b, Test&& test) const {
    if (edges_.empty()) return false;
    bool looked_up = false;                 // (every key is some tile's: no sentinel key)
    std::uint64_t tile_key = 0;             // the tile looked up last
    const std::uint32_t* begins = nullptr;  // of tile_key's cells; nullptr: empty tile
    // Inlined by force: with the obstacle vertices read from fixed point (an int-to-double
    // conversion, a product and a sum each), GCC called the lambda for every cell instead
    // (2 % more instructions for the whole Monaco build).
    return for_cells_along(a, b, kCellM, [&](std::int64_t c, std::int64_t r) ROADCROSS_INLINE {
      const std::uint64_t k = key(c >> kTileShift, r >> kTileShift);
      if (!looked_up || k != tile_key) looked_up = true, tile_key = k, begins = tile_begins(k);
      if (!begins) return false;
      const std::size_t cell = cell_in_tile(c, r);
      // A tile's last cell ends where the next tile's first begins (the sentinel at the end).
      for (std::uint32_t e = begins[cell]; e < begins[cell + 1]; ++e) {
        if (test(edges_[e])) return true;
      }
      return false;
    });
  }

  /// True when test(edge index) is true for an edge in a cell that meets the convex polygon
  /// `polygon` (its vertices in order, as convex_hull gives them) widened by margin_m (>= 0,
  /// metres; below a cell). Every cell that any_along visits for a segment inside the polygon
  /// is among them: a row's columns span the polygon's extent in the row widened by the margin
  /// and for_cells_along's slack, and the margin (1-2 mm) is far above the rounding (1e-11 of a
  /// cell). Cells are visited row by row; an edge in several cells is offered once for each.
  template <typename Test>
  bool any_in_polygon(const std::vector<PlanePoint>& polygon, double margin_m, Test&& test) const {
    if (edges_.empty() || polygon.empty()) return false;
    const double m = margin_m / kCellM + 1e-6;  // in cells; 1e-6: for_cells_along's slack
    // The polygon's sides in cells, each with 1 / its height (a multiplication per row instead
    // of a division: the rounding differs by 1e-16, far inside the margin).
    struct Side {
      double ax, ay, bx, by, inverse_height;
    };
    thread_local std::vector<Side> sides;
    sides.clear();
    double y_min = polygon[0].y / kCellM, y_max = y_min;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const PlanePoint& pa = polygon[i];
      const PlanePoint& pb = polygon[i + 1 < polygon.size() ? i + 1 : 0];
      const double ay = pa.y / kCellM, by = pb.y / kCellM;
      sides.push_back({pa.x / kCellM, ay, pb.x / kCellM, by, by != ay ? 1.0 / (by - ay) : 0.0});
      y_min = std::min(y_min, ay), y_max = std::max(y_max, ay);
    }
    const std::int64_t first_row = floor_to_int(y_min - m), last_row = floor_to_int(y_max + m);
    for (std::int64_t row = first_row; row <= last_row; ++row) {
      // The polygon's x extent in the strip of rows lo..hi: attained on its boundary, so the
      // union of its edges' parts in the strip (a single vertex: the vertex).
      const double lo = double(row) - m, hi = double(row + 1) + m;
      double x0 = std::numeric_limits<double>::infinity(), x1 = -x0;
      for (const Side& side : sides) {
        const double ax = side.ax, ay = side.ay, bx = side.bx, by = side.by;
        if (std::max(ay, by) < lo || std::min(ay, by) > hi) continue;
        double ex0 = std::min(ax, bx), ex1 = std::max(ax, bx);
        if (by != ay) {
          const double t0 = std::clamp((lo - ay) * side.inverse_height, 0.0, 1.0);
          const double t1 = std::clamp((hi - ay) * side.inverse_height, 0.0, 1.0);
          ex0 = ax + t0 * (bx - ax), ex1 = ax + t1 * (bx - ax);
          if (ex0 > ex1) std::swap(ex0, ex1);
        }
        x0 = std::min(x0, ex0), x1 = std::max(x1, ex1);
      }
      if (!(x0 <= x1)) continue;  // the widened y range's end rows may hold no part
      const std::int64_t c0 = floor_to_int(x0 - m), c1 = floor_to_int(x1 + m);
      bool looked_up = false;
      std::uint64_t tile_key = 0;
      const std::uint32_t* begins = nullptr;
      for (std::int64_t c = c0; c <= c1; ++c) {
        const std::uint64_t k = key(c >> kTileShift, row >> kTileShift);
        if (!looked_up || k != tile_key) looked_up = true, tile_key = k, begins = tile_begins(k);
        if (!begins) continue;
        const std::size_t cell = cell_in_tile(c, row);
        for (std::uint32_t e = begins[cell]; e < begins[cell + 1]; ++e) {
          if (test(edges_[e])) return true;
        }
      }
    }
    return false;
  }

  std::size_t tiles() const { return begins_.size() / kTileCells; }
  /// (edge, cell) pairs filed.
  std::size_t entries() const { return edges_.size(); }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t tile = 0;  ///< tile index: its cells are begins_[kTileCells * tile ...]
    bool used = false;
  };

  /// ends(i, a, b): false when id i is no edge, else true with its two ends in a and b.
  template <typename Ends>
  void build(std::size_t ids, Ends&& ends) {
    if (ids > std::numeric_limits<std::uint32_t>::max())
      throw std::length_error("sight: more than 2^32 - 1 obstacle edge ids");
    table_.assign(64, Slot{});
    mask_ = table_.size() - 1;
    PlanePoint from, to;
    for (std::size_t i = 0; i < ids; ++i) {
      if (!ends(i, from, to)) continue;
      for_cells_along(from, to, kCellM, [&](std::int64_t c, std::int64_t r) {
        ++begins_[cell_index(c, r)];  // the count, for now
        return false;
      });
    }
    // Counts -> ends (inclusive prefix sums); the second walk, run backwards over the edges,
    // files each edge at --end, which leaves every cell's begin in place.
    begins_.push_back(0);
    // The tile table's growth slack goes before the entries are allocated (its copy then adds
    // nothing to the peak).
    begins_.shrink_to_fit();
    std::uint32_t sum = 0;
    for (std::uint32_t& b : begins_) b = (sum += b);
    edges_.resize(sum);
    for (std::size_t i = ids; i-- > 0;) {
      if (!ends(i, from, to)) continue;
      for_cells_along(from, to, kCellM, [&](std::int64_t c, std::int64_t r) {
        edges_[--begins_[cell_index(c, r)]] = static_cast<std::uint32_t>(i);
        return false;
      });
    }
  }

  static std::size_t cell_in_tile(std::int64_t column, std::int64_t row) {
    return static_cast<std::size_t>(((row & (kTileSide - 1)) << kTileShift) |
                                    (column & (kTileSide - 1)));
  }
  /// The begins_ index of cell (column, row), adding its tile when new (construction only).
  std::size_t cell_index(std::int64_t column, std::int64_t row) {
    const std::uint64_t k = key(column >> kTileShift, row >> kTileShift);
    std::size_t at = hash(k) & mask_;
    while (table_[at].used && table_[at].key != k) at = (at + 1) & mask_;
    if (!table_[at].used) {
      table_[at] = {k, static_cast<std::uint32_t>(tiles()), true};
      begins_.resize(begins_.size() + kTileCells, 0);
      const std::uint32_t tile = table_[at].tile;
      if (2 * tiles() > table_.size()) grow();
      return kTileCells * tile + cell_in_tile(column, row);
    }
    return kTileCells * table_[at].tile + cell_in_tile(column, row);
  }
  const std::uint32_t* tile_begins(std::uint64_t k) const {
    for (std::size_t at = hash(k) & mask_; table_[at].used; at = (at + 1) & mask_) {
      if (table_[at].key == k) return begins_.data() + kTileCells * table_[at].tile;
    }
    return nullptr;
  }
  void grow() {
    std::vector<Slot> old(table_.size() * 2);
    old.swap(table_);
    mask_ = table_.size() - 1;
    for (const Slot& slot : old) {
      if (!slot.used) continue;
      std::size_t at = hash(slot.key) & mask_;
      while (table_[at].used) at = (at + 1) & mask_;
      table_[at] = slot;
    }
  }
  static std::uint64_t key(std::int64_t column, std::int64_t row) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(column)) << 32) |
           static_cast<std::uint32_t>(row);
  }
  /// Fibonacci hashing; the product's high half depends on both the column (high 32 bits of k)
  /// and the row (the low half alone would see only the row: a row of tiles in one probe chain).
  static std::size_t hash(std::uint64_t k) {
    return static_cast<std::size_t>((k * 0x9E3779B97F4A7C15ull) >> 32);
  }

  std::vector<Slot> table_;  ///< occupied tiles, at most half full
  std::size_t mask_ = 0;
  /// Per tile, where each of its cells' edge lists begins in edges_ (tile by tile, row by row);
  /// one sentinel at the end.
  std::vector<std::uint32_t> begins_;
  std::vector<std::uint32_t> edges_;  ///< edge indices, cell by cell
};

/// Sorts the edges by the tile and then the cell of their first end (both row by row), so that
/// the edges of a cell, and of the cells along a line, lie together in memory: in way order an
/// edge a line tests is anywhere in the array (68 MB at 10x Monaco), each one a cache miss. The
/// answers do not depend on the order (a line is blocked when any edge blocks it).
inline void sort_by_cell(std::vector<ObstacleEdge>& edges) {
  const auto cell_key = [](const ObstacleEdge& e) {
    const std::int64_t column = floor_to_int(e.a.x / EdgeGrid::kCellM);
    const std::int64_t row = floor_to_int(e.a.y / EdgeGrid::kCellM);
    return std::tuple{row >> EdgeGrid::kTileShift, column >> EdgeGrid::kTileShift, row, column};
  };
  std::sort(edges.begin(), edges.end(), [&](const ObstacleEdge& x, const ObstacleEdge& y) {
    return cell_key(x) < cell_key(y);
  });
}

/// A line of sight in plan, from the eye (ex, ey) by (rx, ry) to the target.
struct PlanLine {
  double ex = 0.0, ey = 0.0, rx = 0.0, ry = 0.0;
  PlanLine(const PlanePoint& eye, const PlanePoint& target)
      : ex(eye.x), ey(eye.y), rx(target.x - eye.x), ry(target.y - eye.y) {}
};

/// True only when fl(num / denom) is certainly below 0 or above 1 (|denom| >= 1e-12), decided
/// without the division. The margins (a quotient above 1e-290 in size, or above 1 + 1e-9) lie
/// far beyond the rounding of the comparison, so no quotient the division would put in [0, 1]
/// is rejected.
inline bool surely_outside_unit(double num, double denom) {
  const double n = std::abs(num), d = std::abs(denom);
  if ((num < 0.0) != (denom < 0.0)) return n > d * 1e-290;  // a negative quotient
  return n > d * (1.0 + 1e-9);                              // a quotient above 1
}

/// Where the sight line crosses the edge a->b: the parameter along the line, or NaN. The same
/// arithmetic as the division form (along_line = (q x s) / (r x s), along_edge = (q x r) /
/// (r x s)) and so the same answers; most edges near a line miss it and are rejected by sign
/// and size before the divisions.
inline double crossing_parameter(const PlanLine& line, const PlanePoint& a, const PlanePoint& b) {
  const double sx = b.x - a.x, sy = b.y - a.y;
  const double denom = line.rx * sy - line.ry * sx;
  if (std::abs(denom) < 1e-12) return NAN;  // parallel: grazing along an edge hides nothing
  const double qx = a.x - line.ex, qy = a.y - line.ey;
  const double edge_num = qx * line.ry - qy * line.rx;
  if (surely_outside_unit(edge_num, denom)) return NAN;
  const double line_num = qx * sy - qy * sx;
  if (surely_outside_unit(line_num, denom)) return NAN;
  const double along_line = line_num / denom;
  const double along_edge = edge_num / denom;
  if (along_line < 0.0 || along_line > 1.0 || along_edge < 0.0 || along_edge > 1.0) return NAN;
  return along_line;
}

/// The convex hull of `points` into `hull` (counter-clockwise, from the lowest-x point;
/// duplicates dropped; `points` is sorted in place). Andrew's monotone chain, dropping a point
/// only when it is certainly inside: the turn's cross product is below minus a bound on its
/// rounding error. A nearly collinear point stays as a vertex, so the polygon may bend inwards
/// by ~1e-14 of its size, but every input point lies in the hull of the vertices returned,
/// which is what the fan test relies on.
inline void convex_hull(std::vector<PlanePoint>& points, std::vector<PlanePoint>& hull) {
  std::sort(points.begin(), points.end(), [](const PlanePoint& p, const PlanePoint& q) {
    return p.x < q.x || (p.x == q.x && p.y < q.y);
  });
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

 private:
  void set_eye_and_reach(const PlanePoint& eye, const std::vector<PlanePoint>& outline) {
    eye_ = eye;
    reach_m_ = 0.0;  // |t - eye|1 is convex: its largest over the hull is at a vertex
    for (const PlanePoint& t : outline) {
      reach_m_ = std::max(reach_m_, std::abs(t.x - eye.x) + std::abs(t.y - eye.y));
    }
    reach_m_ += 2 * kOutlineSlackM;
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
    // beside one of its two long sides.
    axes_.clear();
    for (std::size_t i = 0; i < hull_.size() && hull_.size() > 1; ++i) {
      const PlanePoint& a = hull_[i];
      const PlanePoint& b = hull_[i + 1 < hull_.size() ? i + 1 : 0];
      const PlanePoint n{-(b.y - a.y), b.x - a.x};
      if (n.x != 0.0 || n.y != 0.0) axes_.push_back({n, 0.0, 0.0});
    }
    // (Insertion sort: a few axes, mostly three.)
    for (std::size_t i = 1; i < axes_.size(); ++i) {
      const Axis axis = axes_[i];
      const double size = std::abs(axis.n.x) + std::abs(axis.n.y);
      std::size_t j = i;
      for (; j > 0 && std::abs(axes_[j - 1].n.x) + std::abs(axes_[j - 1].n.y) < size; --j) {
        axes_[j] = axes_[j - 1];
      }
      axes_[j] = axis;
    }
    axes_.push_back({{1.0, 0.0}, 0.0, 0.0});
    axes_.push_back({{0.0, 1.0}, 0.0, 0.0});
    for (Axis& axis : axes_) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const PlanePoint& v : rel_hull_) {
        const double d = axis.n.x * v.x + axis.n.y * v.y;
        lo = std::min(lo, d), hi = std::max(hi, d);
      }
      const double gap = kGapM * (std::abs(axis.n.x) + std::abs(axis.n.y));
      axis.below = lo - gap, axis.above = hi + gap;
    }
  }

 public:
  /// True only when no line of the fan can be crossed by the edge a->b (see the class).
  bool edge_clear(const PlanePoint& a, const PlanePoint& b) const {
    constexpr double kU = std::numeric_limits<double>::epsilon() / 2;
    constexpr double kFarM = 1e5;
    const PlanePoint ra{a.x - eye_.x, a.y - eye_.y}, rb{b.x - eye_.x, b.y - eye_.y};
    const double qa = std::abs(ra.x) + std::abs(ra.y), qb = std::abs(rb.x) + std::abs(rb.y);
    if (!(qa < kFarM && qb < kFarM && reach_m_ < kFarM)) return false;
    if (!separated(ra, rb)) return false;
    const double sx = b.x - a.x, sy = b.y - a.y;
    const double s1 = std::abs(sx) + std::abs(sy);
    const double m = reach_m_ + s1 + 2 * qa;
    const double cross = ra.x * sy - ra.y * sx;  // q x s
    return std::abs(cross) > 8 * kU * s1 * m * (reach_m_ / kMarginM + 2);
  }

 private:
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
    PlanePoint n;                     ///< the direction
    double below = 0.0, above = 0.0;  ///< a segment entirely outside these is separated
  };

  /// A separating axis with a gap of kGapM between the fan's points and the segment ra->rb
  /// (both relative to the eye).
  bool separated(const PlanePoint& ra, const PlanePoint& rb) const {
    for (const Axis& axis : axes_) {
      const double pa = axis.n.x * ra.x + axis.n.y * ra.y;
      const double pb = axis.n.x * rb.x + axis.n.y * rb.y;
      if (std::min(pa, pb) >= axis.above || std::max(pa, pb) <= axis.below) return true;
    }
    // The edge's own normal against the hull's vertices (every point is in their hull).
    const PlanePoint n{-(rb.y - ra.y), rb.x - ra.x};
    const double n1 = std::abs(n.x) + std::abs(n.y);
    if (!(n1 > 0.0)) return false;
    const double pa = n.x * ra.x + n.y * ra.y, pb = n.x * rb.x + n.y * rb.y;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const PlanePoint& v : rel_hull_) {
      const double d = n.x * v.x + n.y * v.y;
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
    return std::min(pa, pb) >= hi + kGapM * n1 || std::max(pa, pb) <= lo - kGapM * n1;
  }

  PlanePoint eye_;
  double reach_m_ = 0.0;            ///< R1: the largest |target - eye|1
  std::vector<PlanePoint> points_;  ///< the targets and the eye (sorted by the hull)
  std::vector<PlanePoint> hull_, rel_hull_;
  std::vector<Axis> axes_;
};

/// An edge that may block a line of a fan: its id and its ends (read once per fan, not per
/// line).
struct CandidateEdge {
  PlanePoint a, b;
  std::uint32_t id = 0;
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
    if (!fan.edge_clear(a, b)) out.push_back({a, b, i});
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
