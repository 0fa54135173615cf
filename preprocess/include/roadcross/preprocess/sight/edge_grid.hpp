// The sight stage's spatial index of obstacle edges and its line-edge crossing test .
// Internal to preprocess/src/sight/sight.cpp; a header so that the unit
// tests reach the pieces. Every change here must leave the stage's answers bit for bit as they
// were: the cells a line visits, the edges filed in them and the crossing arithmetic are the
// same as before; only the memory layout and cheap certain rejects are new.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "roadcross/preprocess/common/huge_pages.hpp"
#include "roadcross/preprocess/common/parallel.hpp"
#include "roadcross/preprocess/sight/obstacle_edge.hpp"

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

  /// The edges' cells filed tile by tile, every cell's edges in increasing index order (the
  /// edges' indices are their positions in the vector). `bands` (>= 1; default: one a core)
  /// only divides the work: the grid is the same for every count.
  explicit EdgeGrid(const std::vector<ObstacleEdge>& edges, unsigned bands = core_count()) {
    build(
        edges.size(),
        [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
          a = edges[i].a, b = edges[i].b;
          return true;
        },
        bands);
  }
  /// The same with the edges' ids in the store (its slots that are no edge are skipped).
  explicit EdgeGrid(const ObstacleEdges& edges, unsigned bands = core_count()) {
    build(
        edges.slots(),
        [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
          if (!edges.is_edge(i)) return false;
          a = edges.a(static_cast<std::uint32_t>(i)), b = edges.b(static_cast<std::uint32_t>(i));
          return true;
        },
        bands);
  }

  /// True when test(edge index) is true for an edge in a cell the segment a->b passes through
  /// (every edge the segment crosses is among them); the cells are visited from a. An edge
  /// listed in two cells along the line is offered twice (remembering the edges offered costs
  /// more than the repeated tests it saves).
  /// (The sight stage now tests each line against its fan's candidates, blocked_among; this
  /// line-by-line walk gives the answer it must equal, and is the tests' reference.)
  template <typename Test>
  bool any_along(const PlanePoint& a, const PlanePoint& b, Test&& test) const {
    if (edges_.empty()) return false;
    bool looked_up = false;                 // (every key is some tile's: no sentinel key)
    std::uint64_t tile_key = 0;             // the tile looked up last
    const std::uint32_t* begins = nullptr;  // of tile_key's cells; nullptr: empty tile
    // Inlined by force: with the obstacle vertices read from fixed point (an int-to-double
    // conversion, a product and a sum each), GCC would call the lambda for every cell instead.
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
    double y_min = polygon[0].y / kCellM, y_max = y_min;
    for (const PlanePoint& p : polygon) {
      y_min = std::min(y_min, p.y / kCellM), y_max = std::max(y_max, p.y / kCellM);
    }
    const std::int64_t first_row = floor_to_int(y_min - m), last_row = floor_to_int(y_max + m);
    // The polygon's x extent in the strip of each row, lo..hi = row - m..row + 1 + m: attained
    // on its boundary, so the union of its sides' parts in the strip (a single vertex: the
    // vertex). Side by side over the rows it may reach (one more each way than its own y range
    // widened by m: rounding moves the test below by ~1e-16 of a row), each row asked as if
    // every side were tried in it; min and max are exact, so the order does not matter.
    const auto rows = static_cast<std::size_t>(last_row - first_row + 1);
    struct Extent {
      double x0, x1;
    };
    thread_local std::vector<Extent> extents;
    if (extents.size() < rows) extents.resize(rows);
    Extent* const extent = extents.data();
    for (std::size_t i = 0; i < rows; ++i) {
      extent[i] = {std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()};
    }
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      // The side in cells, with 1 / its height (a multiplication per row instead of a division:
      // the rounding differs by 1e-16, far inside the margin).
      const PlanePoint& pa = polygon[i];
      const PlanePoint& pb = polygon[i + 1 < polygon.size() ? i + 1 : 0];
      const double ax = pa.x / kCellM, ay = pa.y / kCellM, bx = pb.x / kCellM, by = pb.y / kCellM;
      const double inverse_height = by != ay ? 1.0 / (by - ay) : 0.0;
      const std::int64_t from = std::max(first_row, floor_to_int(std::min(ay, by) - m) - 1);
      const std::int64_t to = std::min(last_row, floor_to_int(std::max(ay, by) + m) + 1);
      for (std::int64_t row = from; row <= to; ++row) {
        const double lo = double(row) - m, hi = double(row + 1) + m;
        if (std::max(ay, by) < lo || std::min(ay, by) > hi) continue;
        double ex0 = std::min(ax, bx), ex1 = std::max(ax, bx);
        if (by != ay) {
          const double t0 = std::clamp((lo - ay) * inverse_height, 0.0, 1.0);
          const double t1 = std::clamp((hi - ay) * inverse_height, 0.0, 1.0);
          ex0 = ax + t0 * (bx - ax), ex1 = ax + t1 * (bx - ax);
          if (ex0 > ex1) std::swap(ex0, ex1);
        }
        const auto at = static_cast<std::size_t>(row - first_row);
        extent[at] = {std::min(extent[at].x0, ex0), std::max(extent[at].x1, ex1)};
      }
    }
    for (std::int64_t row = first_row; row <= last_row; ++row) {
      const auto [x0, x1] = extent[static_cast<std::size_t>(row - first_row)];
      if (!(x0 <= x1)) continue;  // the widened y range's end rows may hold no part
      const std::int64_t c0 = floor_to_int(x0 - m), c1 = floor_to_int(x1 + m);
      // The row's cells tile by tile: within a tile a row's cells are consecutive in its table,
      // each one's edges beginning where the one before ends, so the edges of the row's cells
      // there are one run (the same edges in the same order as cell by cell, without a look at
      // each empty cell).
      for (std::int64_t c = c0; c <= c1;) {
        const std::int64_t last = std::min(c1, c | (kTileSide - 1));  // in this tile
        const std::uint32_t* begins = tile_begins(key(c >> kTileShift, row >> kTileShift));
        if (begins) {
          const std::uint32_t end = begins[cell_in_tile(last, row) + 1];
          for (std::uint32_t e = begins[cell_in_tile(c, row)]; e < end; ++e) {
            if (test(edges_[e])) return true;
          }
        }
        c = last + 1;
      }
    }
    return false;
  }

  std::size_t tiles() const { return begins_.size() / kTileCells; }
  /// The largest |b - a|1 of the edges filed, metres (NaN-free inputs; 0 without edges).
  double longest_edge_m() const { return longest_edge_m_; }
  /// (edge, cell) pairs filed.
  std::size_t entries() const { return edges_.size(); }

  using EdgeIds = std::vector<std::uint32_t, UninitialisedAllocator<std::uint32_t>>;
  /// Where each cell's edges begin in cell_edges(): tile by tile (numbered in the order the
  /// edges, in index order and each along its walk, first reach them), in a tile row by row;
  /// then the end (tests).
  const EdgeIds& cell_begins() const { return begins_; }
  /// The edge indices, cell by cell (tests).
  const EdgeIds& cell_edges() const { return edges_; }
  /// The number of the tile of cells (column, row), or -1 when it has no edge (tests).
  std::int64_t tile_number(std::int64_t column, std::int64_t row) const {
    const std::uint32_t* begins = tile_begins(key(column >> kTileShift, row >> kTileShift));
    return begins ? static_cast<std::int64_t>((begins - begins_.data()) / kTileCells) : -1;
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t tile = 0;  ///< tile index: its cells are begins_[kTileCells * tile ...]
    bool used = false;
  };

  /// ends(i, a, b): false when id i is no edge, else true with its two ends in a and b.
  ///
  /// Four passes. (1) One thread numbers the tiles in the order the edges' walks first reach
  /// them; most edges lie in one tile, found from their box without a walk. (2) The cells'
  /// counts, (3) the prefix sums and (4) the filing, backwards over the edges at --end, which
  /// leaves every cell's begin in place and its edges in increasing index order. The counting
  /// and the filing are split in bands of tile rows, one a thread, each walking only the rows
  /// of its band of every edge (an edge across a band's border is walked in part by both): a
  /// cell is written by one thread only, and each cell's edges arrive in the same order as in
  /// one walk of them all, so the grid is the same for every number of bands. The passes'
  /// tables are the grid's own: no thread has a copy of one.
  template <typename Ends>
  void build(std::size_t ids, const Ends& ends, unsigned bands) {
    if (ids > std::numeric_limits<std::uint32_t>::max())
      throw std::length_error("sight: more than 2^32 - 1 obstacle edge ids");
    table_.assign(64, Slot{});
    mask_ = table_.size() - 1;
    // (1) The tiles, with the cells reaching each (the bands' weights).
    std::vector<std::uint64_t> weight;
    std::uint64_t last_key = 0;
    std::uint32_t last_tile = 0;
    const auto reach = [&](std::uint64_t k, std::uint64_t cells) {
      // An edge's cells, and a building's consecutive edges, are mostly in one tile.
      if (weight.empty() || k != last_key) {
        last_key = k, last_tile = add_tile(k);
        if (last_tile == weight.size()) weight.push_back(0);
      }
      weight[last_tile] += cells;
    };
    PlanePoint from, to;
    for (std::size_t i = 0; i < ids; ++i) {
      if (!ends(i, from, to)) continue;
      longest_edge_m_ =
          std::max(longest_edge_m_, std::abs(to.x - from.x) + std::abs(to.y - from.y));
      // The box of the edge's ends in cells, widened by 1e-3 cell: the walk's cells lie within
      // for_cells_along's slack (1e-6 cell) and its rounding (below 1e-4 cell for coordinates
      // below 2^40 m) of it. In one tile, that tile is the only one the walk reaches.
      const double x0 = std::min(from.x, to.x) / kCellM, x1 = std::max(from.x, to.x) / kCellM;
      const double y0 = std::min(from.y, to.y) / kCellM, y1 = std::max(from.y, to.y) / kCellM;
      constexpr double kBoxSlack = 1e-3;
      const std::int64_t c0 = floor_to_int(x0 - kBoxSlack), c1 = floor_to_int(x1 + kBoxSlack);
      const std::int64_t r0 = floor_to_int(y0 - kBoxSlack), r1 = floor_to_int(y1 + kBoxSlack);
      if (c0 >> kTileShift == c1 >> kTileShift && r0 >> kTileShift == r1 >> kTileShift) {
        reach(key(c0 >> kTileShift, r0 >> kTileShift),
              static_cast<std::uint64_t>(c1 - c0 + r1 - r0 + 1));
        continue;
      }
      for_cells_along(from, to, kCellM, [&](std::int64_t c, std::int64_t r) {
        reach(key(c >> kTileShift, r >> kTileShift), 1);
        return false;
      });
    }
    const std::vector<std::int64_t> starts = band_starts(weight, std::max(bands, 1u));
    const auto in_bands = [&](auto&& walk_band) {
      parallel_for<NoState>(
          starts.size(),
          [&](std::size_t band, NoState&) {
            const std::int64_t lo = starts[band];
            const std::int64_t hi = band + 1 < starts.size()
                                        ? starts[band + 1] - 1
                                        : std::numeric_limits<std::int64_t>::max();
            walk_band(lo, hi);
          },
          1, static_cast<unsigned>(starts.size()));
    };
    // (2) The counts, each band zeroing its own tiles first (the page faults, too, on every
    // core). Huge pages: a fault per 2 MiB instead of per 4 KiB (~10 us each here).
    resize_on_huge_pages(begins_, kTileCells * weight.size() + 1);  // + 1: the sentinel
    begins_.back() = 0;
    in_bands([&](std::int64_t lo, std::int64_t hi) {
      for (const Slot& slot : table_) {
        const std::int64_t row = static_cast<std::int32_t>(static_cast<std::uint32_t>(slot.key));
        if (slot.used && row >= lo >> kTileShift && row <= hi >> kTileShift) {
          std::fill_n(begins_.begin() + static_cast<std::ptrdiff_t>(kTileCells * slot.tile),
                      kTileCells, 0u);
        }
      }
      for_cells_in_rows(ids, ends, lo, hi, false,
                        [&](std::size_t, std::size_t cell) { ++begins_[cell]; });
    });
    // (3) Counts -> ends (inclusive prefix sums).
    std::uint32_t sum = 0;
    for (std::uint32_t& b : begins_) b = (sum += b);
    // (4) The filing (edges_ is left unwritten until then).
    resize_on_huge_pages(edges_, sum);
    in_bands([&](std::int64_t lo, std::int64_t hi) {
      for_cells_in_rows(ids, ends, lo, hi, true, [&](std::size_t i, std::size_t cell) {
        edges_[--begins_[cell]] = static_cast<std::uint32_t>(i);
      });
    });
  }

  /// The first cell row of each band (the first: the lowest row there is), at tile rows'
  /// borders, each band with about the same weight (cells reached) of at most `bands`.
  std::vector<std::int64_t> band_starts(const std::vector<std::uint64_t>& weight,
                                        unsigned bands) const {
    std::vector<std::pair<std::int64_t, std::uint64_t>> rows;  // (tile row, weight) per tile
    rows.reserve(weight.size());
    std::uint64_t total = 0;
    for (const Slot& slot : table_) {
      if (!slot.used) continue;
      rows.emplace_back(static_cast<std::int32_t>(static_cast<std::uint32_t>(slot.key)),
                        weight[slot.tile]);
      total += weight[slot.tile];
    }
    std::sort(rows.begin(), rows.end());
    std::vector<std::int64_t> starts{std::numeric_limits<std::int64_t>::min()};
    std::uint64_t before = 0;  // the weight of the rows below rows[k]
    for (std::size_t k = 0; k < rows.size(); before += rows[k++].second) {
      if (starts.size() == bands) break;
      if (k > 0 && rows[k].first != rows[k - 1].first && before * bands >= total * starts.size()) {
        starts.push_back(rows[k].first * kTileSide);
      }
    }
    return starts;
  }

  /// Tile number of key k, adding the tile when new (numbered in order).
  std::uint32_t add_tile(std::uint64_t k) {
    std::size_t at = hash(k) & mask_;
    while (table_[at].used && table_[at].key != k) at = (at + 1) & mask_;
    if (table_[at].used) return table_[at].tile;
    const auto tile = static_cast<std::uint32_t>(tile_count_++);
    table_[at] = {k, tile, true};
    if (2 * tile_count_ > table_.size()) grow();
    return tile;
  }

  /// Calls visit(i, begins_ index) for every cell in rows lo..hi (cell rows, inclusive) of the
  /// walk of every edge i, the edges in increasing index order (or decreasing: `backwards`);
  /// an edge's cells in its rows are those of for_cells_along (the same arithmetic), in
  /// another order. Reads only.
  template <typename Ends, typename Visit>
  void for_cells_in_rows(std::size_t ids, const Ends& ends, std::int64_t lo, std::int64_t hi,
                         bool backwards, Visit&& visit) const {
    std::uint64_t cached_key = 0;
    std::size_t cached_base = 0;
    bool cached = false;
    PlanePoint from, to;
    for (std::size_t n = 0; n < ids; ++n) {
      const std::size_t i = backwards ? ids - 1 - n : n;
      if (!ends(i, from, to)) continue;
      // The walk's lowest and highest rows (CellsAlong's arithmetic) first: most edges of the
      // other bands end here.
      const double y0 = std::min(from.y, to.y) / kCellM, y1 = std::max(from.y, to.y) / kCellM;
      const std::int64_t row0 = std::max(floor_to_int(y0 - CellsAlong::kSlack), lo);
      const std::int64_t row1 = std::min(floor_to_int(y1 + CellsAlong::kSlack), hi);
      if (row0 > row1) continue;
      const CellsAlong cells(from, to, kCellM);
      for (std::int64_t row = row0; row <= row1; ++row) {
        std::int64_t c0 = 0, c1 = 0;
        cells.columns(row, c0, c1);
        for (std::int64_t c = c0; c <= c1; ++c) {
          const std::uint64_t k = key(c >> kTileShift, row >> kTileShift);
          if (!cached || k != cached_key) {
            const std::uint32_t* begins = tile_begins(k);
            // (The first pass numbered every tile a walk reaches: never, but not silently.)
            if (!begins) throw std::logic_error("EdgeGrid: a cell in no numbered tile");
            cached = true, cached_key = k;
            cached_base = static_cast<std::size_t>(begins - begins_.data());
          }
          visit(i, cached_base + cell_in_tile(c, row));
        }
      }
    }
  }

  static std::size_t cell_in_tile(std::int64_t column, std::int64_t row) {
    return static_cast<std::size_t>(((row & (kTileSide - 1)) << kTileShift) |
                                    (column & (kTileSide - 1)));
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
  std::size_t tile_count_ = 0;
  /// Per tile, where each of its cells' edge lists begins in edges_ (tile by tile, row by row);
  /// one sentinel at the end.
  EdgeIds begins_;
  EdgeIds edges_;  ///< edge indices, cell by cell
  double longest_edge_m_ = 0.0;
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

/// The terms of crossing_parameter that depend only on an edge a->b and the eye, not on the
/// target: s = b - a, q = a - eye and q x s. A fan's candidate edges keep them (fan_candidates),
/// so that each of the fan's lines computes only its own terms; the arithmetic is the same.
struct EdgeFromEye {
  double sx = 0.0, sy = 0.0, qx = 0.0, qy = 0.0;
  double line_num = 0.0;  ///< q x s
};

inline EdgeFromEye edge_from_eye(const PlanePoint& eye, const PlanePoint& a, const PlanePoint& b) {
  EdgeFromEye e;
  e.sx = b.x - a.x, e.sy = b.y - a.y;
  e.qx = a.x - eye.x, e.qy = a.y - eye.y;
  e.line_num = e.qx * e.sy - e.qy * e.sx;
  return e;
}

/// crossing_parameter for the line from the eye by (rx, ry), with the edge's terms from
/// edge_from_eye(that eye, a, b): the same value, bit for bit.
inline double crossing_parameter(double rx, double ry, const EdgeFromEye& e) {
  const double denom = rx * e.sy - ry * e.sx;
  if (std::abs(denom) < 1e-12) return NAN;  // parallel: grazing along an edge hides nothing
  const double edge_num = e.qx * ry - e.qy * rx;
  if (surely_outside_unit(edge_num, denom)) return NAN;
  if (surely_outside_unit(e.line_num, denom)) return NAN;
  const double along_line = e.line_num / denom;
  const double along_edge = edge_num / denom;
  if (along_line < 0.0 || along_line > 1.0 || along_edge < 0.0 || along_edge > 1.0) return NAN;
  return along_line;
}

/// Where the sight line crosses the edge a->b: the parameter along the line, or NaN. The same
/// arithmetic as the division form (along_line = (q x s) / (r x s), along_edge = (q x r) /
/// (r x s)) and so the same answers; most edges near a line miss it and are rejected by sign
/// and size before the divisions.
inline double crossing_parameter(const PlanLine& line, const PlanePoint& a, const PlanePoint& b) {
  return crossing_parameter(line.rx, line.ry, edge_from_eye({line.ex, line.ey}, a, b));
}

}  // namespace roadcross::preprocess::sight_detail
