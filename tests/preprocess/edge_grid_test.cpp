// The sight stage's edge grid and crossing test (edge_grid.hpp): hand-made cases, plus two
// checks against independent references — the tile-grouped grid against a plain set of cells
// per edge, and the crossing test with its early rejects against the division form it replaced
// (bit for bit, on random and near-degenerate edges).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/preprocess/sight/fan.hpp"
#include "roadcross/preprocess/sight/shadow.hpp"

namespace rp = roadcross::preprocess;
namespace sd = roadcross::preprocess::sight_detail;
using roadcross::schema::PlanePoint;

namespace {

rp::ObstacleEdge edge(double ax, double ay, double bx, double by) {
  return {{ax, ay}, {bx, by}, 0.0f, 10.0f};
}

/// The edge indices any_along offers for a->b, in order (test never stops the walk).
std::vector<std::uint32_t> offered(const sd::EdgeGrid& grid, PlanePoint a, PlanePoint b) {
  std::vector<std::uint32_t> out;
  grid.any_along(a, b, [&](std::uint32_t i) {
    out.push_back(i);
    return false;
  });
  return out;
}

using Cells = std::vector<std::pair<std::int64_t, std::int64_t>>;

/// The cells of a->b as for_cells_along found them before floor_to_int, with std::floor (the
/// reference the walk must equal cell for cell).
Cells reference_cells(const PlanePoint& a, const PlanePoint& b, double cell_m) {
  constexpr double kSlack = 1e-6;
  const double ax = a.x / cell_m, ay = a.y / cell_m, bx = b.x / cell_m, by = b.y / cell_m;
  const double y_min = std::min(ay, by), y_max = std::max(ay, by);
  const bool up = by >= ay, right = bx >= ax;
  const auto first_row =
      static_cast<std::int64_t>(std::floor((up ? y_min : y_max) + (up ? -kSlack : kSlack)));
  const auto last_row =
      static_cast<std::int64_t>(std::floor((up ? y_max : y_min) + (up ? kSlack : -kSlack)));
  Cells out;
  for (std::int64_t row = first_row;; row += up ? 1 : -1) {
    double x0 = std::min(ax, bx), x1 = std::max(ax, bx);
    if (by != ay) {
      const double t0 = std::clamp((double(row) - kSlack - ay) / (by - ay), 0.0, 1.0);
      const double t1 = std::clamp((double(row + 1) + kSlack - ay) / (by - ay), 0.0, 1.0);
      x0 = ax + t0 * (bx - ax);
      x1 = ax + t1 * (bx - ax);
      if (x0 > x1) std::swap(x0, x1);
    }
    const auto c0 = static_cast<std::int64_t>(std::floor(x0 - kSlack));
    const auto c1 = static_cast<std::int64_t>(std::floor(x1 + kSlack));
    if (right) {
      for (std::int64_t c = c0; c <= c1; ++c) out.emplace_back(c, row);
    } else {
      for (std::int64_t c = c1; c >= c0; --c) out.emplace_back(c, row);
    }
    if (row == last_row) return out;
  }
}

Cells cells_of_line(const PlanePoint& a, const PlanePoint& b) {
  Cells out;
  sd::for_cells_along(a, b, 16.0, [&](std::int64_t c, std::int64_t r) {
    out.emplace_back(c, r);
    return false;
  });
  return out;
}

/// The division form of the crossing test, as sight.cpp had it before the early rejects.
double reference_crossing(const PlanePoint& e, const PlanePoint& t, const PlanePoint& a,
                          const PlanePoint& b) {
  const double rx = t.x - e.x, ry = t.y - e.y, sx = b.x - a.x, sy = b.y - a.y;
  const double denom = rx * sy - ry * sx;
  if (std::abs(denom) < 1e-12) return NAN;
  const double qx = a.x - e.x, qy = a.y - e.y;
  const double along_line = (qx * sy - qy * sx) / denom;
  const double along_edge = (qx * ry - qy * rx) / denom;
  if (along_line < 0.0 || along_line > 1.0 || along_edge < 0.0 || along_edge > 1.0) return NAN;
  return along_line;
}

}  // namespace

TEST(EdgeGrid, FloorToIntMatchesFloor) {
  EXPECT_EQ(sd::floor_to_int(2.7), 2);
  EXPECT_EQ(sd::floor_to_int(2.0), 2);
  EXPECT_EQ(sd::floor_to_int(0.0), 0);
  EXPECT_EQ(sd::floor_to_int(-0.0), 0);
  EXPECT_EQ(sd::floor_to_int(-1e-300), -1);
  EXPECT_EQ(sd::floor_to_int(-2.0), -2);
  EXPECT_EQ(sd::floor_to_int(-1.5), -2);
  EXPECT_EQ(sd::floor_to_int(312500.99999999994), 312500);
}

TEST(EdgeGrid, CellsOfAHorizontalLine) {
  // Row 0, x from 1 to 40 m: columns 0, 1 and 2 of 16 m cells, in order from a; backwards
  // from b the other way round.
  std::vector<std::pair<std::int64_t, std::int64_t>> cells;
  sd::for_cells_along({1.0, 5.0}, {40.0, 5.0}, 16.0, [&](std::int64_t c, std::int64_t r) {
    cells.emplace_back(c, r);
    return false;
  });
  EXPECT_EQ(cells, (std::vector<std::pair<std::int64_t, std::int64_t>>{{0, 0}, {1, 0}, {2, 0}}));
  cells.clear();
  sd::for_cells_along({40.0, 5.0}, {1.0, 5.0}, 16.0, [&](std::int64_t c, std::int64_t r) {
    cells.emplace_back(c, r);
    return false;
  });
  EXPECT_EQ(cells, (std::vector<std::pair<std::int64_t, std::int64_t>>{{2, 0}, {1, 0}, {0, 0}}));
}

TEST(EdgeGrid, CellsAreThoseOfTheStdFloorWalkEvenOnCellBoundaries) {
  // UTM-sized coordinates: random lines, and lines through cell corners and along cell edges
  // (their row ends fall on cell boundaries).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> cells(-20, 20);
  const double x0 = 731232.0, y0 = 4849872.0;  // multiples of 16
  std::size_t compared = 0;
  for (int k = 0; k < 20000; ++k) {
    PlanePoint a{x0 + 300 * u(rng), y0 + 300 * u(rng)};
    PlanePoint b{a.x + 300 * u(rng), a.y + 300 * u(rng)};
    if (k % 3 == 1) {  // corner to corner
      a = {x0 + 16.0 * cells(rng), y0 + 16.0 * cells(rng)};
      b = {a.x + 16.0 * cells(rng), a.y + 16.0 * cells(rng)};
    } else if (k % 3 == 2) {  // a corner to a point whose row crossings are at whole cells
      a = {x0 + 16.0 * cells(rng), y0 + 16.0 * cells(rng)};
      const int n = cells(rng);
      b = {a.x + 16.0 * 3 * n, a.y + 16.0 * n + 5.0};
    }
    const Cells want = reference_cells(a, b, 16.0);
    ASSERT_EQ(cells_of_line(a, b), want) << k;
    compared += want.size();
  }
  EXPECT_GT(compared, 100000u);
}

TEST(EdgeGrid, OffersTheEdgesOfTheCellsAlongALineAcrossTiles) {
  // Tiles are 16 cells = 256 m. Edge 0 in cell (0, 0); edge 1 in cell (20, 0) (the next tile);
  // edge 2 in cell (-1, 0) (the tile west of the origin); edge 3 spans cells (5..6, 0); edge 4
  // is in row 3 (y 48-64 m), off the line.
  const std::vector<rp::ObstacleEdge> edges{edge(2, 2, 5, 5), edge(325, 1, 330, 8),
                                            edge(-10, 3, -5, 3), edge(90, 4, 100, 4),
                                            edge(20, 50, 30, 55)};
  const sd::EdgeGrid grid(edges);
  EXPECT_EQ(grid.tiles(), 3u);
  EXPECT_EQ(grid.entries(), 6u);  // edge 3 is in two cells
  // Along row 0 from x = -8 to 335: cells -1, 0, ..., 20 in that order; edge 3 in cells 5 and 6.
  EXPECT_EQ(offered(grid, {-8, 8}, {335, 8}), (std::vector<std::uint32_t>{2, 0, 3, 3, 1}));
  // From the other end, the other way round.
  EXPECT_EQ(offered(grid, {335, 8}, {-8, 8}), (std::vector<std::uint32_t>{1, 3, 3, 0, 2}));
  // A line from x = 40 to 79 (cells 2 to 4) passes no edge's cell.
  EXPECT_TRUE(offered(grid, {40, 8}, {79, 8}).empty());
  // The walk stops at the first edge the test accepts.
  std::vector<std::uint32_t> seen;
  EXPECT_TRUE(grid.any_along({-8, 8}, {335, 8}, [&](std::uint32_t i) {
    seen.push_back(i);
    return i == 3;
  }));
  EXPECT_EQ(seen, (std::vector<std::uint32_t>{2, 0, 3}));
  // No edges at all: nothing offered.
  const sd::EdgeGrid empty(std::vector<rp::ObstacleEdge>{});
  EXPECT_TRUE(offered(empty, {0, 0}, {100, 100}).empty());
}

TEST(EdgeGrid, AgreesWithAPlainSetOfCellsPerEdge) {
  // Random edges and lines around UTM-like coordinates (both signs of cell index): every edge
  // offered once per cell the line and the edge share, in the cells' order along the line.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> where(-600.0, 600.0), step(-40.0, 40.0);
  std::vector<rp::ObstacleEdge> edges;
  for (int i = 0; i < 3000; ++i) {
    const double x = where(rng), y = where(rng);
    edges.push_back(edge(x, y, x + step(rng), y + step(rng)));
  }
  std::vector<std::set<std::pair<std::int64_t, std::int64_t>>> cells_of(edges.size());
  for (std::size_t i = 0; i < edges.size(); ++i) {
    sd::for_cells_along(edges[i].a, edges[i].b, 16.0, [&](std::int64_t c, std::int64_t r) {
      cells_of[i].insert({c, r});
      return false;
    });
  }
  const sd::EdgeGrid grid(edges);
  std::uniform_real_distribution<double> reach(-300.0, 300.0);
  for (int k = 0; k < 200; ++k) {
    const PlanePoint a{where(rng), where(rng)};
    const PlanePoint b{a.x + reach(rng), a.y + reach(rng)};
    std::vector<std::uint32_t> expected;
    sd::for_cells_along(a, b, 16.0, [&](std::int64_t c, std::int64_t r) {
      for (std::size_t i = 0; i < edges.size(); ++i) {
        if (cells_of[i].count({c, r})) expected.push_back(static_cast<std::uint32_t>(i));
      }
      return false;
    });
    ASSERT_EQ(offered(grid, a, b), expected) << "line " << k;
  }
}

namespace {

/// The grid as one walk of every edge in index order makes it, from for_cells_along alone:
/// tiles numbered as first reached, then per tile its cells' begins row by row, the end, and
/// the edges cell by cell in increasing index order.
struct PlainGrid {
  std::vector<std::pair<std::int64_t, std::int64_t>> tiles;  // (column, row), by number
  std::vector<std::uint32_t> begins, edges;
};

template <typename EdgeEnds>
PlainGrid plain_grid(std::size_t ids, const EdgeEnds& ends) {
  std::map<std::pair<std::int64_t, std::int64_t>, std::size_t> number;
  std::vector<std::vector<std::vector<std::uint32_t>>> lists;  // per tile, per cell
  PlainGrid out;
  for (std::size_t i = 0; i < ids; ++i) {
    PlanePoint a, b;
    if (!ends(i, a, b)) continue;
    sd::for_cells_along(a, b, 16.0, [&](std::int64_t c, std::int64_t r) {
      const std::pair<std::int64_t, std::int64_t> tile{c >> 4, r >> 4};
      const auto [at, added] = number.emplace(tile, out.tiles.size());
      if (added) out.tiles.push_back(tile), lists.emplace_back(256);
      lists[at->second][static_cast<std::size_t>((r & 15) * 16 + (c & 15))].push_back(
          static_cast<std::uint32_t>(i));
      return false;
    });
  }
  for (const auto& tile : lists) {
    for (const auto& cell : tile) {
      out.begins.push_back(static_cast<std::uint32_t>(out.edges.size()));
      out.edges.insert(out.edges.end(), cell.begin(), cell.end());
    }
  }
  out.begins.push_back(static_cast<std::uint32_t>(out.edges.size()));
  return out;
}

void expect_grid_is(const sd::EdgeGrid& grid, const PlainGrid& want, const std::string& what) {
  ASSERT_EQ(grid.tiles(), want.tiles.size()) << what;
  for (std::size_t t = 0; t < want.tiles.size(); ++t) {
    const auto [column, row] = want.tiles[t];
    ASSERT_EQ(grid.tile_number(column * 16 + 5, row * 16 + 11), static_cast<std::int64_t>(t))
        << what << ": tile " << t;
  }
  ASSERT_EQ(std::vector<std::uint32_t>(grid.cell_begins().begin(), grid.cell_begins().end()),
            want.begins)
      << what;
  ASSERT_EQ(std::vector<std::uint32_t>(grid.cell_edges().begin(), grid.cell_edges().end()),
            want.edges)
      << what;
  // Each cell's edges in increasing index order (the filing backwards, band by band).
  for (std::size_t cell = 0; cell + 1 < want.begins.size(); ++cell) {
    for (std::uint32_t e = want.begins[cell] + 1; e < want.begins[cell + 1]; ++e) {
      ASSERT_LT(grid.cell_edges()[e - 1], grid.cell_edges()[e]) << what << ": cell " << cell;
    }
  }
}

/// Random edges over 16 x 16 tiles around the origin (both signs of cell index): short ones
/// (most in one tile), long ones across several tiles and so across the bands' borders, and
/// ones on tile borders (whole multiples of 256 m: a walk's slack reaches the next tile).
std::vector<rp::ObstacleEdge> edges_across_tiles(std::uint64_t seed, int count) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> where(-2048.0, 2048.0), step(-40.0, 40.0),
      far(-900.0, 900.0);
  std::uniform_int_distribution<int> border(-8, 8), kind(0, 9);
  std::vector<rp::ObstacleEdge> edges;
  for (int i = 0; i < count; ++i) {
    const double x = where(rng), y = where(rng);
    switch (kind(rng)) {
      case 0:
        edges.push_back(edge(x, y, x + far(rng), y + far(rng)));
        break;
      case 1:  // along a tile row's border
        edges.push_back(edge(x, 256.0 * border(rng), x + far(rng), 256.0 * border(rng)));
        break;
      case 2: {  // a tile corner to a point
        const double cx = 256.0 * border(rng), cy = 256.0 * border(rng);
        edges.push_back(edge(cx, cy, cx + step(rng), cy + step(rng)));
        break;
      }
      default:
        edges.push_back(edge(x, y, x + step(rng), y + step(rng)));
    }
  }
  return edges;
}

}  // namespace

TEST(EdgeGrid, EveryNumberOfBandsGivesTheGridOfOneWalkOfAllEdges) {
  // The bands (threads) split the counting and filing by tile rows; edges across a band's
  // border are walked by both. The grid must be that of one walk in index order, bit for bit.
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const std::vector<rp::ObstacleEdge> edges = edges_across_tiles(seed, 4000);
    const PlainGrid want =
        plain_grid(edges.size(), [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
          a = edges[i].a, b = edges[i].b;
          return true;
        });
    ASSERT_GT(want.tiles.size(), 150u);
    for (const unsigned bands : {1u, 2u, 3u, 7u, 16u, 1000u}) {
      const sd::EdgeGrid grid(edges, bands);
      expect_grid_is(grid, want,
                     "seed " + std::to_string(seed) + ", " + std::to_string(bands) + " bands");
    }
  }
}

TEST(EdgeGrid, OneAndTwoBandsGiveTheSameGridOfAnObstacleEdgesStore) {
  // Ids are slots (headers are none): the same grid with gaps in the ids.
  const std::vector<rp::ObstacleEdge> edges = edges_across_tiles(11, 3000);
  const rp::ObstacleEdges store(edges);
  const PlainGrid want =
      plain_grid(store.slots(), [&](std::size_t i, PlanePoint& a, PlanePoint& b) {
        if (!store.is_edge(i)) return false;
        a = store.a(static_cast<std::uint32_t>(i)), b = store.b(static_cast<std::uint32_t>(i));
        return true;
      });
  const sd::EdgeGrid one(store, 1), two(store, 2);
  expect_grid_is(one, want, "1 band");
  expect_grid_is(two, want, "2 bands");
  EXPECT_EQ(one.longest_edge_m(), two.longest_edge_m());
  // And the lines it offers, as a check of the tile table the bands read.
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> where(-2048.0, 2048.0), reach(-300.0, 300.0);
  for (int k = 0; k < 300; ++k) {
    const PlanePoint a{where(rng), where(rng)};
    const PlanePoint b{a.x + reach(rng), a.y + reach(rng)};
    ASSERT_EQ(offered(two, a, b), offered(one, a, b)) << "line " << k;
  }
}

TEST(EdgeGrid, NoEdgesWithManyBands) {
  const sd::EdgeGrid grid(std::vector<rp::ObstacleEdge>{}, 4);
  EXPECT_EQ(grid.tiles(), 0u);
  EXPECT_EQ(grid.entries(), 0u);
  EXPECT_EQ(std::vector<std::uint32_t>(grid.cell_begins().begin(), grid.cell_begins().end()),
            std::vector<std::uint32_t>{0});
}

TEST(ObstacleEdges, ARingIsItsVerticesOnceAfterAHeader) {
  // A 10 m square with a band of 2-9 m: header, 4 corners, the first corner again (6 slots of
  // 8 bytes for 4 edges, against 4 x 40 bytes as separate edges); then a wall of one edge.
  rp::ObstacleEdges edges;
  edges.begin_run(2.0f, 9.0f);
  for (const PlanePoint& p : std::vector<PlanePoint>{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}})
    edges.add_vertex(p);
  edges.begin_run(0.0f, 2.5f);
  edges.add_vertex({20, 0});
  edges.add_vertex({20, 30});
  EXPECT_EQ(edges.slots(), 9u);
  EXPECT_EQ(edges.edges(), 5u);
  std::vector<std::size_t> ids;
  for (std::size_t i = 0; i < edges.slots(); ++i) {
    if (edges.is_edge(i)) ids.push_back(i);
  }
  EXPECT_EQ(ids, (std::vector<std::size_t>{1, 2, 3, 4, 7}));
  EXPECT_EQ(edges.a(3).x, 10.0);
  EXPECT_EQ(edges.a(3).y, 10.0);
  EXPECT_EQ(edges.b(3).x, 0.0);
  EXPECT_EQ(edges.b(3).y, 10.0);
  EXPECT_EQ(edges.bottom_m(4), 2.0f);
  EXPECT_EQ(edges.top_m(4), 9.0f);
  const rp::ObstacleEdge wall = edges[7];
  EXPECT_EQ(wall.a.x, 20.0);
  EXPECT_EQ(wall.b.y, 30.0);
  EXPECT_EQ(wall.bottom_m, 0.0f);
  EXPECT_EQ(wall.top_m, 2.5f);
  // The slots by hand (default frame: origin (0, 0), 1024 units a metre): the header holds
  // 2.0f = 0x40000000 with the sign bit set, and 9.0f = 0x41100000; (10, 10) is 10240 units.
  EXPECT_EQ(static_cast<std::uint32_t>(edges.slot(0).x), 0xC0000000u);
  EXPECT_EQ(static_cast<std::uint32_t>(edges.slot(0).y), 0x41100000u);
  EXPECT_EQ(edges.slot(3).x, 10240);
  EXPECT_EQ(edges.slot(3).y, 10240);
  EXPECT_EQ(edges.slot(8).y, 30 * 1024);
}

TEST(ObstacleEdges, LongChainsAreCutIntoRunsOfAtMost64Edges) {
  // A fence of 130 edges along x (vertices x = 0, 1, ..., 130): runs of 64, 64 and 2 edges,
  // each after a header and starting at the last vertex of the one before: 130 + 2 + 2 * 2 =
  // 136 slots. Written vertex by vertex and as a chain, the same slots.
  std::vector<PlanePoint> vertices;
  std::vector<rp::FixedSlot> raw;
  for (int x = 0; x <= 130; ++x) {
    vertices.push_back({double(x), 5.0});
    raw.push_back({x * 1024, 5 * 1024});  // in the default frame: 2^-10 m units from (0, 0)
  }
  rp::ObstacleEdges added;
  added.begin_run(0.0f, 1.5f);
  for (const PlanePoint& p : vertices) added.add_vertex(p);
  EXPECT_EQ(rp::ObstacleEdges::slots_for_chain(130), 136u);
  ASSERT_EQ(added.slots(), 136u);
  EXPECT_EQ(added.edges(), 130u);
  // Run 2's header is slot 66 (after header 0 and vertices 0..64 in slots 1..65); its first
  // vertex, slot 67, is x = 64 again.
  EXPECT_FALSE(added.is_edge(65));
  EXPECT_FALSE(added.is_edge(66));
  EXPECT_EQ(added.a(67).x, 64.0);
  EXPECT_EQ(added.b(67).x, 65.0);
  EXPECT_EQ(added.top_m(134), 1.5f);  // the last edge, 129 -> 130, finds its header at 132
  EXPECT_EQ(added.a(134).x, 129.0);
  rp::ObstacleEdges::Slots written(136);
  const rp::FixedSlot* end =
      rp::ObstacleEdges::write_chain(written.data(), 0.0f, 1.5f, raw.data(), raw.data() + 130);
  EXPECT_EQ(end, written.data() + 136);
  const rp::ObstacleEdges adopted = rp::ObstacleEdges::adopt(written, rp::VertexFrame());
  for (std::size_t i = 0; i < 136; ++i) {
    ASSERT_EQ(adopted.is_edge(i), added.is_edge(i)) << i;
    if (!added.is_edge(i)) continue;
    const auto id = static_cast<std::uint32_t>(i);
    EXPECT_EQ(adopted.a(id).x, added.a(id).x);
    EXPECT_EQ(adopted.b(id).x, added.b(id).x);
    EXPECT_EQ(adopted.top_m(id), 1.5f);
  }
  // A run of 65 edges, or vertices before any header, are refused.
  rp::ObstacleEdges::Slots too_long(67, rp::FixedSlot{1024, 1024});
  too_long[0] = rp::ObstacleEdges::header(0.0f, 1.0f);
  EXPECT_THROW(rp::ObstacleEdges::adopt(too_long, rp::VertexFrame()), std::logic_error);
  too_long.pop_back();
  EXPECT_NO_THROW(rp::ObstacleEdges::adopt(too_long, rp::VertexFrame()));
  EXPECT_THROW(rp::ObstacleEdges::adopt({{1024, 1024}, {2048, 2048}}, rp::VertexFrame()),
               std::logic_error);
}

TEST(ObstacleEdges, SeparateEdgesJoinWhenOneStartsWhereTheLastEndsWithItsBand) {
  // (0,0)->(5,0)->(5,5) chain (same band); (5,5)->(9,9) has another band: a new run; (1,1)->
  // (2,2) does not start at (9,9): a new run. Slots: [H 0 1 2] [H 2 3] [H 4 5].
  const rp::ObstacleEdges edges{{{0, 0}, {5, 0}, 0.0f, 8.0f},
                                {{5, 0}, {5, 5}, 0.0f, 8.0f},
                                {{5, 5}, {9, 9}, 0.0f, 3.0f},
                                {{1, 1}, {2, 2}, 0.0f, 3.0f}};
  EXPECT_EQ(edges.slots(), 10u);
  EXPECT_EQ(edges.edges(), 4u);
  EXPECT_EQ(edges[2].b.y, 5.0);
  EXPECT_EQ(edges[2].top_m, 8.0f);
  EXPECT_EQ(edges[5].a.x, 5.0);
  EXPECT_EQ(edges[5].top_m, 3.0f);
  EXPECT_EQ(edges[8].a.x, 1.0);
}

TEST(EdgeGrid, OffersTheIdsOfAnObstacleEdgesStore) {
  // Runs as in the test above, one metre off the cell lines: edge ids 1, 2, 5, 8 in cell (0, 0)
  // and 11 in cell (2, 2). Along row 0 from x = -8 to 30 (cells -1 to 1) the grid offers the
  // ids of cell (0, 0) in increasing order.
  const rp::ObstacleEdges edges{{{1, 1}, {6, 1}, 0.0f, 8.0f},
                                {{6, 1}, {6, 6}, 0.0f, 8.0f},
                                {{6, 6}, {10, 10}, 0.0f, 3.0f},
                                {{2, 2}, {3, 3}, 0.0f, 3.0f},
                                {{40, 40}, {41, 41}, 0.0f, 3.0f}};
  const sd::EdgeGrid grid(edges);
  EXPECT_EQ(grid.entries(), 5u);
  EXPECT_EQ(offered(grid, {-8, 8}, {30, 8}), (std::vector<std::uint32_t>{1, 2, 5, 8}));
  EXPECT_EQ(offered(grid, {35, 40}, {45, 40}), (std::vector<std::uint32_t>{11}));
}

TEST(EdgeGrid, SortByCellOrdersByTileThenCellOfTheFirstEnd) {
  // First ends: cell (18, 0) in tile (1, 0); cells (0, 0), (1, 0) and (0, 1) in tile (0, 0);
  // cell (0, 18) in tile (0, 1) (tile row 1 comes after tile row 0); cell (-1, 0) in tile (-1, 0).
  std::vector<rp::ObstacleEdge> edges{edge(300, 10, 0, 0), edge(5, 5, 0, 0),   edge(20, 3, 0, 0),
                                      edge(3, 20, 0, 0),   edge(5, 300, 0, 0), edge(-3, 2, 0, 0)};
  sd::sort_by_cell(edges);
  std::vector<std::pair<double, double>> firsts;
  for (const rp::ObstacleEdge& e : edges) firsts.emplace_back(e.a.x, e.a.y);
  EXPECT_EQ(firsts, (std::vector<std::pair<double, double>>{
                        {-3, 2}, {5, 5}, {20, 3}, {3, 20}, {300, 10}, {5, 300}}));
}

TEST(EdgeGrid, SurelyOutsideUnitRejectsOnlyQuotientsOutsideZeroOne) {
  EXPECT_TRUE(sd::surely_outside_unit(-1.0, 2.0));  // -0.5
  EXPECT_TRUE(sd::surely_outside_unit(3.0, -2.0));  // -1.5
  EXPECT_TRUE(sd::surely_outside_unit(3.0, 2.0));   // 1.5
  EXPECT_TRUE(sd::surely_outside_unit(-3.0, -2.0));
  EXPECT_FALSE(sd::surely_outside_unit(-1.0, -2.0));  // 0.5
  EXPECT_FALSE(sd::surely_outside_unit(0.0, 2.0));
  EXPECT_FALSE(sd::surely_outside_unit(-0.0, 2.0));  // -0 is not below 0
  EXPECT_FALSE(sd::surely_outside_unit(0.0, -2.0));
  EXPECT_FALSE(sd::surely_outside_unit(2.0, 2.0));  // exactly 1
  // Just above 1, within the margin: left to the division (which may round it to 1).
  EXPECT_FALSE(sd::surely_outside_unit(2.0 * (1.0 + 1e-12), 2.0));
}

TEST(EdgeGrid, CrossingParameterByHand) {
  const sd::PlanLine line({0, 0}, {10, 0});
  EXPECT_DOUBLE_EQ(sd::crossing_parameter(line, {5, -1}, {5, 1}), 0.5);
  EXPECT_DOUBLE_EQ(sd::crossing_parameter(line, {10, 0}, {10, 5}), 1.0);     // touches the target
  EXPECT_DOUBLE_EQ(sd::crossing_parameter(line, {2, 3}, {2, 0}), 0.2);       // ends on the line
  EXPECT_TRUE(std::isnan(sd::crossing_parameter(line, {5, 1}, {5, 2})));     // short of it
  EXPECT_TRUE(std::isnan(sd::crossing_parameter(line, {12, -1}, {12, 1})));  // beyond the target
  EXPECT_TRUE(std::isnan(sd::crossing_parameter(line, {-1, -1}, {-1, 1})));  // behind the eye
  EXPECT_TRUE(std::isnan(sd::crossing_parameter(line, {1, 0}, {4, 0})));     // along it
}

TEST(EdgeGrid, CrossingParameterIsTheDivisionFormBitForBit) {
  // UTM-sized coordinates; edges crossing, missing, touching at their ends and nearly parallel.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double x0 = 731234.56, y0 = 4849876.54;
  int crossings = 0;
  for (int k = 0; k < 200000; ++k) {
    const PlanePoint e{x0 + 300 * u(rng), y0 + 300 * u(rng)};
    const PlanePoint t{e.x + 300 * u(rng), e.y + 300 * u(rng)};
    PlanePoint a{e.x + 300 * u(rng), e.y + 300 * u(rng)};
    PlanePoint b{a.x + 20 * u(rng), a.y + 20 * u(rng)};
    switch (k % 4) {
      case 1:  // an end on the line
        a = {e.x + 0.5 * (1 + u(rng)) * (t.x - e.x), e.y + 0.5 * (1 + u(rng)) * (t.y - e.y)};
        break;
      case 2:  // nearly parallel to the line, near it
        a = {e.x + 0.3 * (t.x - e.x), e.y + 0.3 * (t.y - e.y) + 1e-9 * u(rng)};
        b = {a.x + 0.5 * (t.x - e.x), a.y + 0.5 * (t.y - e.y) + 1e-9 * u(rng)};
        break;
      case 3:  // an end at the eye or the target
        a = (k % 8 == 3) ? e : t;
        break;
      default:
        break;
    }
    const double want = reference_crossing(e, t, a, b);
    const double got = sd::crossing_parameter(sd::PlanLine(e, t), a, b);
    crossings += std::isnan(want) ? 0 : 1;
    ASSERT_EQ(std::isnan(got), std::isnan(want)) << k;
    if (!std::isnan(want)) {
      ASSERT_EQ(got, want) << k;
    }
  }
  EXPECT_GT(crossings, 20000);  // the comparison saw many crossings, not only misses
}

// ---- The fan test (issue 8): many lines of sight from one eye cleared at once. ----

namespace {

bool same_points(const std::vector<PlanePoint>& got,
                 const std::vector<std::pair<double, double>>& want) {
  if (got.size() != want.size()) return false;
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (got[i].x != want[i].first || got[i].y != want[i].second) return false;
  }
  return true;
}

/// Exact orientation sign of (b - a) x (c - a) for small integer-valued coordinates.
double cross(const PlanePoint& a, const PlanePoint& b, const PlanePoint& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

/// Distance from p to segment a-b (plain formula, used only with a generous tolerance).
double point_segment_m(const PlanePoint& p, const PlanePoint& a, const PlanePoint& b) {
  const double sx = b.x - a.x, sy = b.y - a.y, len2 = sx * sx + sy * sy;
  const double t =
      len2 > 0 ? std::clamp(((p.x - a.x) * sx + (p.y - a.y) * sy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(p.x - (a.x + t * sx), p.y - (a.y + t * sy));
}

/// A random eye within 1 km of a point of UTM zone 32 and a wiggly road ahead of it: 2-32
/// positions 5 m apart, starting 5-255 m away (straight for every third `k`). Fills `eye` and
/// `targets` (cleared first).
void random_fan_road(std::mt19937_64& rng, int k, PlanePoint& eye,
                     std::vector<PlanePoint>& targets) {
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::uniform_int_distribution<int> size(2, 32);
  const double x0 = 731234.56, y0 = 4849876.54;
  eye = {x0 + 1000 * u(rng), y0 + 1000 * u(rng)};
  targets.clear();
  double heading = 3.2 * u(rng), px = eye.x + 4 * u(rng), py = eye.y + 4 * u(rng);
  const double turn = 0.05 * u(rng) * (k % 3 == 0 ? 0.0 : 1.0), start = 5 + 250 * unit(rng);
  px += start * std::cos(heading), py += start * std::sin(heading);
  for (int j = 0, n = size(rng); j < n; ++j) {
    targets.push_back({px, py});
    heading += turn;
    px += 5 * std::cos(heading), py += 5 * std::sin(heading);
  }
}

}  // namespace

TEST(FanHull, SquareWithInsideCollinearAndRepeatedPoints) {
  // The square (0,0)-(4,4), its centre, a repeated corner: the four corners, counter-clockwise
  // from the lowest x (then lowest y).
  const std::vector<PlanePoint> square{{4, 4}, {0, 0}, {2, 2}, {4, 0}, {0, 4}, {4, 4}, {1, 3}};
  EXPECT_TRUE(same_points(sd::convex_hull(square), {{0, 0}, {4, 0}, {4, 4}, {0, 4}}));
  // A point on an edge is nearly collinear: the hull keeps it (never drops a point that might
  // be outside), which is still a hull of every point.
  const std::vector<PlanePoint> on_edge{{0, 0}, {2, 0}, {4, 0}, {2, 3}};
  EXPECT_TRUE(same_points(sd::convex_hull(on_edge), {{0, 0}, {2, 0}, {4, 0}, {2, 3}}));
  // Fewer than three distinct points come back as they are (sorted, unique).
  EXPECT_TRUE(same_points(sd::convex_hull({{3, 1}, {1, 1}, {3, 1}}), {{1, 1}, {3, 1}}));
  EXPECT_TRUE(same_points(sd::convex_hull({{5, 5}}), {{5, 5}}));
}

TEST(FanHull, EveryPointIsInsideTheHullOfRandomSets) {
  // Integer coordinates (exact orientations); many collinear triples.
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> c(-6, 6), n(1, 12);
  for (int k = 0; k < 5000; ++k) {
    std::vector<PlanePoint> points(static_cast<std::size_t>(n(rng)));
    for (PlanePoint& p : points) p = {double(c(rng)), double(c(rng))};
    const std::vector<PlanePoint> hull = sd::convex_hull(points);
    ASSERT_FALSE(hull.empty());
    if (hull.size() < 3) continue;
    for (std::size_t i = 0; i < hull.size(); ++i) {  // counter-clockwise, no right turn
      const PlanePoint& a = hull[i];
      const PlanePoint& b = hull[(i + 1) % hull.size()];
      const PlanePoint& d = hull[(i + 2) % hull.size()];
      ASSERT_GE(cross(a, b, d), 0.0) << k;
      for (const PlanePoint& p : points) ASSERT_GE(cross(a, b, p), 0.0) << k;
    }
  }
}

TEST(FanClear, HandMadeEdgesAroundAFan) {
  // Eye at the origin, targets along y = 10 from x = 10 to 40: the hull is the triangle
  // (0,0), (10,10), (40,10). Shifted to UTM-sized coordinates.
  const double x0 = 731232.0, y0 = 4849872.0;
  const auto at = [&](double x, double y) { return PlanePoint{x0 + x, y0 + y}; };
  sd::Fan fan;
  fan.reset(at(0, 0), {at(10, 10), at(20, 10), at(30, 10), at(40, 10)});
  EXPECT_EQ(fan.hull().size(), 5u);                      // the collinear targets stay as vertices
  EXPECT_TRUE(fan.edge_clear(at(0, 12), at(50, 12)));    // 2 m beyond the targets' row
  EXPECT_TRUE(fan.edge_clear(at(20, 0), at(40, 5)));     // below the triangle
  EXPECT_TRUE(fan.edge_clear(at(-5, 1), at(-1, 3)));     // behind the eye
  EXPECT_FALSE(fan.edge_clear(at(25, 5), at(25, 20)));   // across the lines
  EXPECT_FALSE(fan.edge_clear(at(15, 9), at(16, 9.5)));  // inside the hull
  EXPECT_FALSE(fan.edge_clear(at(0, 10.0005), at(50, 10.0005)));  // 0.5 mm from the targets
  EXPECT_TRUE(fan.edge_clear(at(0, 10.002), at(50, 10.002)));     // 2 mm from them
  // Clear of the hull by 5 m, but on the line through the eye and the last target, so the
  // crossing test's rounding could call it a crossing: not cleared.
  EXPECT_FALSE(fan.edge_clear(at(44, 11), at(48, 12)));
  // The separating axis is the edge's own normal: the edge passes the vertex (40, 10)
  // diagonally 0.5 m away.
  EXPECT_TRUE(fan.edge_clear(at(40.0 + 0.5 * std::sqrt(0.5) + 5, 10 + 0.5 * std::sqrt(0.5) - 5),
                             at(40.0 + 0.5 * std::sqrt(0.5) - 5, 10 + 0.5 * std::sqrt(0.5) + 5)));
}

TEST(FanClear, EdgeApartIsTheSeparationAloneAndSuchEdgesCastNoShadow) {
  // The fan of HandMadeEdgesAroundAFan: the triangle (0,0), (10,10), (40,10). edge_apart asks
  // only for the 1 mm gap; the flat-ground search reads shadows (leg_shadow on the leg from
  // (10, 10) to (40, 10)), which an edge set apart never casts.
  const double x0 = 731232.0, y0 = 4849872.0;
  const auto at = [&](double x, double y) { return PlanePoint{x0 + x, y0 + y}; };
  sd::Fan fan;
  fan.reset(at(0, 0), {at(10, 10), at(20, 10), at(30, 10), at(40, 10)});
  const sd::BlockingFractions whole{0.0, 1.0};
  const auto shadow = [&](const PlanePoint& a, const PlanePoint& b) {
    return sd::leg_shadow(at(0, 0), at(10, 10), at(40, 10), a, b, whole);
  };
  EXPECT_TRUE(fan.edge_apart(at(0, 10.002), at(50, 10.002)));  // 2 mm beyond the targets
  EXPECT_TRUE(shadow(at(0, 10.002), at(50, 10.002)).empty());
  EXPECT_FALSE(fan.edge_apart(at(0, 10.0005), at(50, 10.0005)));  // 0.5 mm: too near
  EXPECT_FALSE(fan.edge_apart(at(15, 9), at(16, 9.5)));           // inside the hull
  // 4.1 m beyond the last target, on the line from the eye through it: edge_clear keeps it
  // (the crossing test's rounding), edge_apart does not, and it hides nothing on the leg.
  EXPECT_FALSE(fan.edge_clear(at(44, 11), at(48, 12)));
  EXPECT_TRUE(fan.edge_apart(at(44, 11), at(48, 12)));
  EXPECT_TRUE(shadow(at(44, 11), at(48, 12)).empty());
  // Across the lines at x = 25 from y = 5 to 20: the line to (x, 10) meets x = 25 at
  // y = 250 / x, inside [5, 20] for x from 25 on, so it hides u = (x - 10) / 30 from 0.5 to 1.
  EXPECT_FALSE(fan.edge_apart(at(25, 5), at(25, 20)));
  const sd::LegShadow across = shadow(at(25, 5), at(25, 20));
  ASSERT_FALSE(across.empty());
  EXPECT_NEAR(across.from, 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(across.to, 1.0);
}

TEST(FanClear, ClearEdgesCrossNoLineOfTheFan) {
  // Random fans (an eye beside a wiggly road, 2-32 consecutive positions) and random edges
  // near them, including edges grazing the lines and edges on the line through the eye and a
  // target: whenever edge_clear says clear, crossing_parameter is NaN for every line of the
  // fan (and the edge is at least the margin from every line).
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::size_t clear = 0, not_clear = 0, grazing_clear = 0;
  for (int k = 0; k < 4000; ++k) {
    PlanePoint eye;
    std::vector<PlanePoint> targets;
    random_fan_road(rng, k, eye, targets);
    sd::Fan fan;
    fan.reset(eye, targets);
    for (int e = 0; e < 60; ++e) {
      const PlanePoint& t =
          targets[std::uniform_int_distribution<std::size_t>(0, targets.size() - 1)(rng)];
      const double along = 1.3 * unit(rng);
      const PlanePoint on{eye.x + along * (t.x - eye.x), eye.y + along * (t.y - eye.y)};
      PlanePoint a, b;
      switch (e % 4) {
        case 0: {  // anywhere near the fan
          a = {on.x + 30 * u(rng), on.y + 30 * u(rng)};
          b = {a.x + 20 * u(rng), a.y + 20 * u(rng)};
          break;
        }
        case 1: {  // an end 0-3 mm beside a line, pointing away or along
          const double len = std::hypot(t.x - eye.x, t.y - eye.y);
          const double nx = -(t.y - eye.y) / len, ny = (t.x - eye.x) / len;
          const double off = 0.003 * u(rng);
          a = {on.x + off * nx, on.y + off * ny};
          const double dir = 3.2 * u(rng);
          b = {a.x + 10 * std::cos(dir), a.y + 10 * std::sin(dir)};
          break;
        }
        case 2: {  // on the line through the eye and a target, beyond either end
          const double s = unit(rng) < 0.5 ? -0.2 * unit(rng) : 1.0 + 0.2 * unit(rng);
          a = {eye.x + s * (t.x - eye.x), eye.y + s * (t.y - eye.y)};
          const double s2 = s + (s < 0 ? -0.1 : 0.1) * unit(rng);
          b = {eye.x + s2 * (t.x - eye.x), eye.y + s2 * (t.y - eye.y)};
          break;
        }
        default: {  // parallel to a line, 0-5 mm from it
          const double len = std::hypot(t.x - eye.x, t.y - eye.y);
          const double nx = -(t.y - eye.y) / len, ny = (t.x - eye.x) / len;
          const double off = 0.005 * u(rng);
          a = {on.x + off * nx, on.y + off * ny};
          b = {a.x + 0.3 * (t.x - eye.x), a.y + 0.3 * (t.y - eye.y)};
          break;
        }
      }
      if (!fan.edge_clear(a, b)) {
        ++not_clear;
        continue;
      }
      ++clear;
      grazing_clear += (e % 4 == 1 || e % 4 == 3) ? 1 : 0;
      for (const PlanePoint& target : targets) {
        const double t_cross = sd::crossing_parameter(sd::PlanLine(eye, target), a, b);
        ASSERT_TRUE(std::isnan(t_cross)) << k << " " << e;
        // Independently: the edge keeps ~the margin from the line (a plain distance, with a
        // tolerance far below the margin).
        const double d = std::min({point_segment_m(a, eye, target), point_segment_m(b, eye, target),
                                   point_segment_m(eye, a, b), point_segment_m(target, a, b)});
        ASSERT_GT(d, 0.999 * sd::Fan::kMarginM) << k << " " << e;
      }
    }
  }
  EXPECT_GT(clear, 50000u);  // both answers well represented
  EXPECT_GT(not_clear, 50000u);
  EXPECT_GT(grazing_clear, 5000u);  // edges 1-5 mm from a line were cleared too
}

TEST(FanClear, EdgesSetApartCastNoShadowOnAnyLeg) {
  // Random fans (an eye beside a wiggly road of 2-32 positions 5 m apart) and random edges
  // near them, grazing the lines or on the line through the eye and a target: whenever
  // edge_apart says apart, leg_shadow finds nothing on any leg between consecutive positions.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const sd::BlockingFractions whole{0.0, 1.0};
  std::size_t apart = 0, near = 0, grazing_apart = 0;
  for (int k = 0; k < 3000; ++k) {
    PlanePoint eye;
    std::vector<PlanePoint> targets;
    random_fan_road(rng, k, eye, targets);
    sd::Fan fan;
    fan.reset(eye, targets);
    for (int e = 0; e < 60; ++e) {
      const PlanePoint& t =
          targets[std::uniform_int_distribution<std::size_t>(0, targets.size() - 1)(rng)];
      const double along = 1.3 * unit(rng);
      const PlanePoint on{eye.x + along * (t.x - eye.x), eye.y + along * (t.y - eye.y)};
      const double len = std::hypot(t.x - eye.x, t.y - eye.y);
      const double nx = -(t.y - eye.y) / len, ny = (t.x - eye.x) / len;
      PlanePoint a, b;
      if (e % 3 == 0) {  // anywhere near the fan
        a = {on.x + 30 * u(rng), on.y + 30 * u(rng)};
        b = {a.x + 20 * u(rng), a.y + 20 * u(rng)};
      } else if (e % 3 == 1) {  // an end 0-3 mm beside a line, pointing anywhere
        const double off = 0.003 * u(rng), dir = 3.2 * u(rng);
        a = {on.x + off * nx, on.y + off * ny};
        b = {a.x + 10 * std::cos(dir), a.y + 10 * std::sin(dir)};
      } else {  // on the line through the eye and a target, beyond either end
        const double s = unit(rng) < 0.5 ? -0.2 * unit(rng) : 1.0 + 0.2 * unit(rng);
        const double s2 = s + (s < 0 ? -0.1 : 0.1) * unit(rng);
        a = {eye.x + s * (t.x - eye.x), eye.y + s * (t.y - eye.y)};
        b = {eye.x + s2 * (t.x - eye.x), eye.y + s2 * (t.y - eye.y)};
      }
      if (!fan.edge_apart(a, b)) {
        ++near;
        continue;
      }
      ++apart;
      grazing_apart += e % 3 == 1 ? 1 : 0;
      for (std::size_t j = 0; j + 1 < targets.size(); ++j) {
        ASSERT_TRUE(sd::leg_shadow(eye, targets[j], targets[j + 1], a, b, whole).empty())
            << k << " " << e << " " << j;
      }
    }
  }
  EXPECT_GT(apart, 40000u);  // both answers well represented
  EXPECT_GT(near, 40000u);
  EXPECT_GT(grazing_apart, 5000u);  // edges 1-3 mm from a line were set apart too
}

TEST(FanClear, GridCellsOfAPolygonHoldEveryCellOfItsLines) {
  // Random edges; random fans: every edge any_along offers for a line of the fan is offered by
  // any_in_polygon for the fan's hull; and a fan any_in_polygon clears (no edge fails
  // edge_clear) has no line that any edge crosses.
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  const double x0 = 731232.0, y0 = 4849872.0;
  std::vector<rp::ObstacleEdge> edges;
  for (int i = 0; i < 3000; ++i) {
    const double x = x0 + 600 * u(rng), y = y0 + 600 * u(rng);
    edges.push_back(edge(x, y, x + 20 * u(rng), y + 20 * u(rng)));
  }
  // Some edges exactly on cell boundaries, and an edge along a cell boundary.
  edges.push_back(edge(x0 + 16, y0 - 40, x0 + 16, y0 + 40));
  edges.push_back(edge(x0 - 40, y0 + 32, x0 + 40, y0 + 32));
  const sd::EdgeGrid grid(edges);
  std::size_t clear_fans = 0, lines_checked = 0;
  for (int k = 0; k < 400; ++k) {
    const PlanePoint eye{x0 + 400 * u(rng), y0 + 400 * u(rng)};
    std::vector<PlanePoint> targets;
    double heading = 3.2 * u(rng);
    const double r0 = 5 + 200 * unit(rng), turn = 0.1 * u(rng);
    double px = eye.x + r0 * std::cos(heading), py = eye.y + r0 * std::sin(heading);
    if (k % 5 == 0) px = x0 + 16.0 * std::round(u(rng) * 20), py = y0 + 32;  // on boundaries
    for (int j = 0, n = 2 + k % 16; j < n; ++j) {
      targets.push_back({px, py});
      heading += turn;
      px += 5 * std::cos(heading), py += 5 * std::sin(heading);
    }
    sd::Fan fan;
    fan.reset(eye, targets);
    std::set<std::uint32_t> in_polygon;
    grid.any_in_polygon(fan.hull(), sd::Fan::kMarginM, [&](std::uint32_t i) {
      in_polygon.insert(i);
      return false;
    });
    bool any_crossing = false;
    for (const PlanePoint& t : targets) {
      for (const std::uint32_t i : offered(grid, eye, t)) {
        ASSERT_TRUE(in_polygon.count(i)) << k;
        any_crossing |=
            !std::isnan(sd::crossing_parameter(sd::PlanLine(eye, t), edges[i].a, edges[i].b));
      }
      ++lines_checked;
    }
    const bool clear = !grid.any_in_polygon(fan.hull(), sd::Fan::kMarginM, [&](std::uint32_t i) {
      return !fan.edge_clear(edges[i].a, edges[i].b);
    });
    if (clear) {
      ++clear_fans;
      ASSERT_FALSE(any_crossing) << k;
    }
  }
  EXPECT_GT(clear_fans, 20u);
  EXPECT_GT(lines_checked, 2000u);
}

/// The cells EdgeGrid::any_in_polygon visits, as it found them before its sides were taken
/// row range by row range: each row tries every side (the reference the walk must equal).
Cells reference_polygon_cells(const std::vector<PlanePoint>& polygon, double margin_m) {
  constexpr double kCellM = 16.0;
  const double m = margin_m / kCellM + 1e-6;
  double y_min = polygon[0].y / kCellM, y_max = y_min;
  for (const PlanePoint& p : polygon) {
    y_min = std::min(y_min, p.y / kCellM), y_max = std::max(y_max, p.y / kCellM);
  }
  Cells out;
  for (auto row = static_cast<std::int64_t>(std::floor(y_min - m));
       row <= static_cast<std::int64_t>(std::floor(y_max + m)); ++row) {
    const double lo = double(row) - m, hi = double(row + 1) + m;
    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const PlanePoint& pa = polygon[i];
      const PlanePoint& pb = polygon[(i + 1) % polygon.size()];
      const double ax = pa.x / kCellM, ay = pa.y / kCellM, bx = pb.x / kCellM, by = pb.y / kCellM;
      if (std::max(ay, by) < lo || std::min(ay, by) > hi) continue;
      double ex0 = std::min(ax, bx), ex1 = std::max(ax, bx);
      if (by != ay) {
        const double inverse_height = 1.0 / (by - ay);
        const double t0 = std::clamp((lo - ay) * inverse_height, 0.0, 1.0);
        const double t1 = std::clamp((hi - ay) * inverse_height, 0.0, 1.0);
        ex0 = ax + t0 * (bx - ax), ex1 = ax + t1 * (bx - ax);
        if (ex0 > ex1) std::swap(ex0, ex1);
      }
      x0 = std::min(x0, ex0), x1 = std::max(x1, ex1);
    }
    if (!(x0 <= x1)) continue;
    for (auto c = static_cast<std::int64_t>(std::floor(x0 - m));
         c <= static_cast<std::int64_t>(std::floor(x1 + m)); ++c) {
      out.emplace_back(c, row);
    }
  }
  return out;
}

TEST(FanClear, PolygonCellsAreThoseOfEveryRowTryingEverySide) {
  // Random fans' hulls (and a few with sides along and vertices on cell boundaries), over a grid
  // with one edge in every cell near them: any_in_polygon offers exactly the edges of the
  // reference's cells, in its order.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double x0 = 731232.0, y0 = 4849872.0;  // a cell corner
  std::vector<rp::ObstacleEdge> edges;
  for (int r = -90; r < 90; ++r) {
    for (int c = -90; c < 90; ++c) {  // a short edge inside each cell of 1.4 km around (x0, y0)
      const double x = x0 + 16.0 * c + 8, y = y0 + 16.0 * r + 8;
      edges.push_back(edge(x, y, x + 1, y + 1));
    }
  }
  for (int r = -40; r < 40; ++r) {
    for (int c = -40; c < 40; ++c) {  // and around (0, 0): cells and tiles of both signs
      edges.push_back(edge(16.0 * c + 3, 16.0 * r + 5, 16.0 * c + 4, 16.0 * r + 6));
    }
  }
  const sd::EdgeGrid grid(edges);
  const auto cell_of = [&](std::uint32_t i) {
    return std::pair{static_cast<std::int64_t>(std::floor(edges[i].a.x / 16.0)),
                     static_cast<std::int64_t>(std::floor(edges[i].a.y / 16.0))};
  };
  std::size_t cells = 0;
  for (int k = 0; k < 600; ++k) {
    std::vector<PlanePoint> hull;
    if (k % 4 == 3) {  // around (0, 0), 1-600 m across
      PlanePoint eye;
      std::vector<PlanePoint> targets;
      random_fan_road(rng, k, eye, targets);
      const double scale = 0.02 + 0.5 * std::abs(u(rng));
      for (PlanePoint& t : targets) t = {(t.x - eye.x) * scale, (t.y - eye.y) * scale};
      targets.push_back({-200 * scale * std::abs(u(rng)), 50 * u(rng)});
      hull = sd::convex_hull(targets);
    } else if (k % 4 == 0) {  // vertices on cell corners and sides along cell boundaries
      const auto on = [&] { return 16.0 * std::round(20 * u(rng)); };
      const PlanePoint a{x0 + on(), y0 + on()};
      hull = sd::convex_hull({a, {a.x + 64, a.y}, {a.x + 64, a.y + on()}, {a.x + on(), a.y + 48}});
    } else {
      PlanePoint eye;
      std::vector<PlanePoint> targets;
      random_fan_road(rng, k, eye, targets);  // scaled by 1/4 towards (x0, y0): inside the grid
      eye = {x0 + (eye.x - 731234.56) / 4, y0 + (eye.y - 4849876.54) / 4};
      for (PlanePoint& t : targets) t = {x0 + (t.x - 731234.56) / 4, y0 + (t.y - 4849876.54) / 4};
      sd::Fan fan;
      fan.reset(eye, targets);
      hull = fan.hull();
    }
    Cells offered_cells;
    grid.any_in_polygon(hull, sd::Fan::kMarginM, [&](std::uint32_t i) {
      offered_cells.push_back(cell_of(i));
      return false;
    });
    const Cells expected = reference_polygon_cells(hull, sd::Fan::kMarginM);
    ASSERT_EQ(offered_cells, expected) << k;
    cells += expected.size();
  }
  EXPECT_GT(cells, 6000u);
}

TEST(FanClear, ReachesAllOfVouchesForTheReachTestsOfEveryOfferedEdge) {
  // Random fans over random edges (some long): wherever reaches_all_of says so, edge_apart of
  // every edge any_in_polygon offers is separated_from; it says no for a fan whose reach or
  // whose grid's longest edge leaves no room under half of the 100 km.
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double x0 = 731234.56, y0 = 4849876.54;
  std::vector<rp::ObstacleEdge> edges;
  for (int i = 0; i < 4000; ++i) {
    const double x = x0 + 1400 * u(rng), y = y0 + 1400 * u(rng), len = i % 50 == 0 ? 2000 : 30;
    edges.push_back(edge(x, y, x + len * u(rng), y + len * u(rng)));
  }
  const sd::EdgeGrid grid(edges);
  EXPECT_GT(grid.longest_edge_m(), 1000.0);
  std::size_t offered = 0, apart = 0;
  for (int k = 0; k < 300; ++k) {
    PlanePoint eye;
    std::vector<PlanePoint> targets;
    random_fan_road(rng, k, eye, targets);
    sd::Fan fan;
    fan.reset(eye, targets);
    ASSERT_TRUE(fan.reaches_all_of(grid.longest_edge_m(), sd::EdgeGrid::kCellM)) << k;
    grid.any_in_polygon(fan.hull(), sd::Fan::kMarginM, [&](std::uint32_t i) {
      ++offered;
      const bool separated = fan.separated_from(edges[i].a, edges[i].b);
      EXPECT_EQ(fan.edge_apart(edges[i].a, edges[i].b), separated) << k << " " << i;
      apart += separated ? 1 : 0;
      return false;
    });
  }
  EXPECT_GT(offered, 2000u);
  EXPECT_GT(apart, offered / 4);
  EXPECT_LT(apart, offered);
  // 30 km of reach plus 20 km of edge is half of kFarM: no longer vouched for.
  sd::Fan far;
  far.reset({x0, y0}, {{x0 + 30000, y0}, {x0 + 30000, y0 + 5}});
  EXPECT_TRUE(far.reaches_all_of(19000.0, sd::EdgeGrid::kCellM));
  EXPECT_FALSE(far.reaches_all_of(20000.0, sd::EdgeGrid::kCellM));
}

TEST(FanClear, TriangleFastPathIsTheHull) {
  // Two targets and the eye that certainly turn: the triangle, counter-clockwise, whichever
  // way round the targets come; collinear ones go through convex_hull (all three kept: the
  // segment there and back).
  sd::Fan fan;
  fan.reset({0, 0}, {{10, 0}, {10, 10}});
  EXPECT_TRUE(same_points(fan.hull(), {{0, 0}, {10, 0}, {10, 10}}));
  fan.reset({0, 0}, {{10, 10}, {10, 0}});
  EXPECT_TRUE(same_points(fan.hull(), {{0, 0}, {10, 0}, {10, 10}}));
  fan.reset({0, 0}, {{5, 5}, {10, 10}});
  EXPECT_TRUE(same_points(fan.hull(), {{0, 0}, {5, 5}, {10, 10}, {5, 5}}));
  EXPECT_TRUE(fan.edge_clear({0, 2}, {3, 10}));    // beside the segment
  EXPECT_FALSE(fan.edge_clear({0, 10}, {10, 0}));  // across it
}

TEST(VertexFrame, AVertexIsReadBackAsTheExactDoubleOfItsNearestUnit) {
  // A 10 km box: origin at the whole metres below its corner, 2^-10 m units. 123.4567 m from
  // the origin is 126 419.66 units: 126 420, read back as 126420 / 1024 = 123.45703125 m.
  const rp::VertexFrame frame =
      rp::VertexFrame::covering({500000.3, 4800000.7}, {510000.0, 4810000.0});
  EXPECT_EQ(frame.origin().x, 500000.0);
  EXPECT_EQ(frame.origin().y, 4800000.0);
  EXPECT_EQ(frame.unit_m(), 1.0 / 1024);
  const rp::FixedSlot s = frame.encode({500123.4567, 4800001.0});
  EXPECT_EQ(s.x, 126420);
  EXPECT_EQ(s.y, 1024);
  EXPECT_EQ(frame.decode(s).x, 500123.45703125);  // exact: no rounding in the decoding
  EXPECT_EQ(frame.decode(s).y, 4800001.0);
  // Random points: within half a unit, and encoding the decoded point gives the same slot.
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> x(500000.3, 510000.0), y(4800000.7, 4810000.0);
  for (int k = 0; k < 10000; ++k) {
    const PlanePoint p{x(rng), y(rng)};
    const rp::FixedSlot q = frame.encode(p);
    const PlanePoint back = frame.decode(q);
    ASSERT_LE(std::abs(back.x - p.x), 0.5 / 1024 + 1e-9);
    ASSERT_LE(std::abs(back.y - p.y), 0.5 / 1024 + 1e-9);
    ASSERT_EQ(back.x, frame.origin().x + std::ldexp(double(q.x), -10));
    const rp::FixedSlot again = frame.encode(back);
    ASSERT_EQ(again.x, q.x);
    ASSERT_EQ(again.y, q.y);
  }
  // Outside the frame: refused.
  EXPECT_THROW(frame.encode({499999.0, 4800001.0}), std::out_of_range);
  EXPECT_THROW(frame.encode({500001.0, 4800000.0 + 2200e3}), std::out_of_range);
}

TEST(VertexFrame, TheUnitIsTheFinestPowerOfTwoThatFitsTheExtent) {
  // 2^31 - 1 units: 2 097.15 km at 2^-10 m, 4 194.3 km at 2^-9, 16 777.2 km at 2^-7.
  EXPECT_EQ(rp::VertexFrame::covering({0, 0}, {2000e3, 10}).unit_m(), 0x1p-10);
  EXPECT_EQ(rp::VertexFrame::covering({0, 0}, {10, 2100e3}).unit_m(), 0x1p-9);
  EXPECT_EQ(rp::VertexFrame::covering({0, 0}, {16000e3, 10}).unit_m(), 0x1p-7);
  try {
    rp::VertexFrame::covering({100e3, 0}, {17100e3, 1000});
    FAIL() << "no error for a 17 000 km extent";
  } catch (const std::length_error& e) {
    EXPECT_NE(std::string(e.what()).find("extent of 17000 km x 1 km"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(rp::VertexFrame::covering({0, 0}, {NAN, 1}), std::invalid_argument);
}

TEST(ObstacleEdges, AHeaderIsToldApartFromAVertexAndKeepsItsBandBitForBit) {
  // x of a vertex is >= 0 (0: the origin); a header's is negative.
  EXPECT_FALSE(rp::ObstacleEdges::is_header(rp::VertexFrame().encode({0.0, 0.0})));
  EXPECT_TRUE(rp::ObstacleEdges::is_header(rp::ObstacleEdges::header(0.0f, 1.0f)));
  const float bottoms[] = {0.0f, -0.0f, 2.5f, 1e-40f, std::numeric_limits<float>::max()};
  const float tops[] = {3.0f, std::numeric_limits<float>::infinity(), 1e-30f, 7.25f, 0.1f};
  for (const float bottom : bottoms) {
    for (const float top : tops) {
      rp::ObstacleEdges edges;
      edges.begin_run(bottom, top);
      edges.add_vertex({1.0, 2.0});
      edges.add_vertex({3.0, 4.0});
      ASSERT_TRUE(rp::ObstacleEdges::is_header(edges.slot(0)));
      ASSERT_TRUE(edges.is_edge(1));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(edges.bottom_m(1)),
                std::bit_cast<std::uint32_t>(bottom));
      EXPECT_EQ(std::bit_cast<std::uint32_t>(edges.top_m(1)), std::bit_cast<std::uint32_t>(top));
    }
  }
  EXPECT_THROW(rp::ObstacleEdges::header(-1.0f, 2.0f), std::invalid_argument);
  EXPECT_THROW(rp::ObstacleEdges::header(NAN, 2.0f), std::invalid_argument);
}

TEST(ObstacleEdges, EdgesGivenAsDoublesAreStoredInTheFrameOfTheirEnds) {
  // Ends 1.0001 m apart: origin (100, 200) (the whole metres below the lowest end), read back
  // as the nearest 1/1024 m: 0.0001 m is 0.1 unit, rounded away.
  const rp::ObstacleEdges edges{{{100.5, 200.25}, {101.5001, 200.25}, 0.0f, 3.0f}};
  EXPECT_EQ(edges.frame().origin().x, 100.0);
  EXPECT_EQ(edges.frame().origin().y, 200.0);
  EXPECT_EQ(edges.a(1).x, 100.5);
  EXPECT_EQ(edges.a(1).y, 200.25);
  EXPECT_EQ(edges.b(1).x, 101.5);
  EXPECT_EQ(edges.slot(2).x, 1536);  // 1.5 m
}

// ---- The fans' candidate edges (issue 8): each line tested against its fan's candidates. ----

TEST(FanCandidates, CellsAlongVisitsAreTheWalksCells) {
  // CellsAlong::visits, asked for every cell near a segment, says yes exactly for the cells the
  // walk visits (the reference walk above), on random lines and lines along cell boundaries.
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> cells(-6, 6);
  const double x0 = 731232.0, y0 = 4849872.0;
  std::size_t visited = 0, asked = 0;
  for (int k = 0; k < 3000; ++k) {
    PlanePoint a{x0 + 300 * u(rng), y0 + 300 * u(rng)};
    PlanePoint b{a.x + 80 * u(rng), a.y + 80 * u(rng)};
    if (k % 2 == 1) {  // corners and boundaries
      a = {x0 + 16.0 * cells(rng), y0 + 16.0 * cells(rng)};
      b = {a.x + 16.0 * cells(rng), a.y + (k % 4 == 1 ? 0.0 : 16.0 * cells(rng))};
    }
    const Cells want = reference_cells(a, b, 16.0);
    const std::set<std::pair<std::int64_t, std::int64_t>> in(want.begin(), want.end());
    const sd::CellsAlong along(a, b, 16.0);
    const auto c_lo = sd::floor_to_int(std::min(a.x, b.x) / 16.0) - 2;
    const auto c_hi = sd::floor_to_int(std::max(a.x, b.x) / 16.0) + 2;
    const auto r_lo = sd::floor_to_int(std::min(a.y, b.y) / 16.0) - 2;
    const auto r_hi = sd::floor_to_int(std::max(a.y, b.y) / 16.0) + 2;
    for (std::int64_t r = r_lo; r <= r_hi; ++r) {
      for (std::int64_t c = c_lo; c <= c_hi; ++c) {
        ASSERT_EQ(along.visits(c, r), in.count({c, r}) == 1) << k << " " << c << " " << r;
        ++asked;
      }
    }
    visited += in.size();
  }
  EXPECT_GT(visited, 20000u);
  EXPECT_GT(asked, 5 * visited);
}

namespace {

/// A wiggly road beside an eye, as KerbSearch follows it: its points and the distance along it
/// of each, and the point at a distance (PathCursor's arithmetic: the leg, then a lerp).
struct TestPath {
  std::vector<PlanePoint> points;
  std::vector<double> at_m;
  PlanePoint at(double d_m) const {
    const auto i = std::size_t(std::upper_bound(at_m.begin(), at_m.end(), d_m) - at_m.begin());
    if (i == 0) return points.front();
    if (i == at_m.size()) return points.back();
    const double t = (d_m - at_m[i - 1]) / (at_m[i] - at_m[i - 1]);
    return {points[i - 1].x + t * (points[i].x - points[i - 1].x),
            points[i - 1].y + t * (points[i].y - points[i - 1].y)};
  }
  /// at(d0_m), the vertices strictly between, at(d1_m): their hull holds at(d) for d between.
  std::vector<PlanePoint> outline(double d0_m, double d1_m) const {
    std::vector<PlanePoint> out{at(d0_m)};
    for (std::size_t i = 0; i < at_m.size(); ++i) {
      if (at_m[i] > d0_m && at_m[i] < d1_m) out.push_back(points[i]);
    }
    out.push_back(at(d1_m));
    return out;
  }
};

}  // namespace

TEST(FanCandidates, EveryLineGetsTheAnswerOfItsOwnWalk) {
  // Random roads (straight, curved, some on cell boundaries), an eye beside each, and edges
  // around them: anywhere near, across the road, 0-5 mm beside a line of sight (ends pointing
  // away or parallel), nearly collinear with a line (beyond either end or overlapping it).
  // For fans of 1-32 positions whose outline starts one position before the first (the last
  // one seen), every line to a position and to random points between (the bisection's) gets
  // the same answer from blocked_among over the fan's candidates as from any_along over the
  // whole grid — the line-by-line test. `blocks` is a crossing in plan and, for 3 edges in 4,
  // a band the line passes (edge_blocks' heights), so crossing edges that do not block occur.
  // Half the roads near the origin, where an edge nearly collinear with a line (case 3) often
  // rounds to a crossing although it lies beyond the line's end, in cells the line never
  // visits (in UTM coordinates the points' own rounding keeps such an edge off the line).
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::size_t lines = 0, hidden = 0, candidates = 0, only_by_candidate = 0, crossing_elsewhere = 0;
  for (int k = 0; k < 300; ++k) {
    const double x0 = k % 2 == 0 ? 731232.0 : 0.0, y0 = k % 2 == 0 ? 4849872.0 : 0.0;
    TestPath path;
    const double spread = k % 2 == 0 ? 40.0 : 1.0;
    const PlanePoint start{x0 + 16.0 * std::round(spread * u(rng)),
                           y0 + 16.0 * std::round(spread * u(rng))};
    double heading = k % 4 == 0 ? 0.0 : 3.2 * u(rng);
    const double turn = k % 3 == 0 ? 0.0 : 0.3 * u(rng);
    PlanePoint p = start;
    path.points.push_back(p), path.at_m.push_back(0.0);
    for (int j = 0; j < 12; ++j) {
      const double leg = 5 + 30 * unit(rng);
      p = {p.x + leg * std::cos(heading), p.y + leg * std::sin(heading)};
      path.points.push_back(p), path.at_m.push_back(path.at_m.back() + leg);
      heading += turn * u(rng);
    }
    const double side = k % 5 == 0 ? 0.0 : 6 * u(rng);  // 0: an eye on the road's line
    const PlanePoint eye = k % 4 == 1 ? PlanePoint{0.0, 0.0}
                                      : PlanePoint{start.x - side * std::sin(heading),
                                                   start.y + side * std::cos(heading)};
    // Positions every 5 m; edges around the lines to some of them.
    const double end_m = path.at_m.back();
    std::vector<rp::ObstacleEdge> edges;
    const int n_edges = 4 + k % 24;
    for (int e = 0; e < n_edges; ++e) {
      const PlanePoint t = path.at(end_m * unit(rng));
      const double along = 1.3 * unit(rng);
      const PlanePoint on{eye.x + along * (t.x - eye.x), eye.y + along * (t.y - eye.y)};
      const double len = std::hypot(t.x - eye.x, t.y - eye.y);
      const double nx = -(t.y - eye.y) / len, ny = (t.x - eye.x) / len;
      PlanePoint a, b;
      switch (e % 10 < 6 ? e % 10 / 2 + 1 : e % 10 == 9 ? 4 : 0) {
        case 0:  // anywhere near
          a = {on.x + 30 * u(rng), on.y + 30 * u(rng)};
          b = {a.x + 15 * u(rng), a.y + 15 * u(rng)};
          break;
        case 1: {  // an end 0-5 mm beside the line, pointing anywhere
          const double off = 0.005 * u(rng), dir = 3.2 * u(rng), l = 8 * unit(rng);
          a = {on.x + off * nx, on.y + off * ny};
          b = {a.x + l * std::cos(dir), a.y + l * std::sin(dir)};
          break;
        }
        case 2: {  // parallel to the line, 0-5 mm from it
          const double off = 0.005 * u(rng), l = 0.5 * unit(rng);
          a = {on.x + off * nx, on.y + off * ny};
          b = {a.x + l * (t.x - eye.x), a.y + l * (t.y - eye.y)};
          break;
        }
        case 3: {  // on the line through the eye and a position: beyond either end, or on it
          const PlanePoint q =
              path.at(std::min(end_m, 5.0 * std::floor(1 + unit(rng) * end_m / 5)));
          const double s = unit(rng) < 0.3 ? -0.3 * unit(rng) : 2.5 * unit(rng);
          const double s2 = s + 0.6 * u(rng);
          a = {eye.x + s * (q.x - eye.x), eye.y + s * (q.y - eye.y)};
          b = {eye.x + s2 * (q.x - eye.x), eye.y + s2 * (q.y - eye.y)};
          break;
        }
        default: {  // short, across the line
          const double l = 3 * unit(rng);
          a = {on.x - l * nx, on.y - l * ny}, b = {on.x + l * nx, on.y + l * ny};
          break;
        }
      }
      edges.push_back(edge(a.x, a.y, b.x, b.y));
    }
    const sd::EdgeGrid grid(edges);
    const auto ends = [&](std::uint32_t i) { return std::pair{edges[i].a, edges[i].b}; };
    const auto blocks_for = [&](const PlanePoint& target) {
      return [&, target](std::uint32_t i) {
        const double t = sd::crossing_parameter(sd::PlanLine(eye, target), edges[i].a, edges[i].b);
        return !std::isnan(t) && i % 4 != 3;  // 3 in 4 edges tall enough
      };
    };
    sd::Fan fan;
    std::vector<sd::CandidateEdge> fan_candidates;
    double seen_m = 0.0;
    for (std::size_t first = 1, n = 1 + std::size_t(k % 8); seen_m < end_m;) {
      const double last_m = std::min(double(first + n - 1) * 5.0, end_m);
      fan.reset(eye, path.outline(seen_m, last_m));
      sd::fan_candidates(grid, fan, ends, fan_candidates);
      candidates += fan_candidates.size();
      std::vector<double> positions;
      for (std::size_t j = 0; j < n; ++j)
        positions.push_back(std::min(double(first + j) * 5.0, end_m));
      for (int j = 0; j < 6; ++j) positions.push_back(seen_m + (last_m - seen_m) * unit(rng));
      positions.push_back(seen_m);
      for (const double d : positions) {
        const PlanePoint target = path.at(d);
        const auto blocks = blocks_for(target);
        const bool want = grid.any_along(eye, target, blocks);
        const sd::PlanLine line(eye, target);
        const auto blocks_candidate = [&](const sd::CandidateEdge& c) {
          EXPECT_EQ(c.a.x, edges[c.id].a.x);  // the candidate's ends are the edge's
          EXPECT_EQ(c.b.y, edges[c.id].b.y);
          // Its crossing terms (from the fan's eye, kept for all the fan's lines) give the
          // crossing of this line with the edge, bit for bit, as the sight stage uses them.
          const double t_kept = sd::crossing_parameter(line.rx, line.ry, c.from_eye);
          const double t_line = sd::crossing_parameter(line, edges[c.id].a, edges[c.id].b);
          EXPECT_TRUE(std::isnan(t_kept) ? std::isnan(t_line)
                                         : std::bit_cast<std::uint64_t>(t_kept) ==
                                               std::bit_cast<std::uint64_t>(t_line))
              << k << " " << d;
          return blocks(c.id);
        };
        const bool got = sd::blocked_among(fan_candidates, eye, target, blocks_candidate);
        ASSERT_EQ(got, want) << k << " " << d;
        ++lines;
        hidden += want ? 1 : 0;
        // Lines that only one candidate blocks (dropping it would change the answer), and
        // candidates that cross the line in plan but lie in none of its cells.
        std::size_t blocking = 0;
        for (const sd::CandidateEdge& c : fan_candidates) {
          if (!blocks(c.id)) continue;
          const std::vector<sd::CandidateEdge> one{c};
          if (sd::blocked_among(one, eye, target, blocks_candidate)) {
            ++blocking;
          } else {
            ++crossing_elsewhere;
          }
        }
        only_by_candidate += blocking == 1 ? 1 : 0;
      }
      seen_m = last_m, first += n, n = std::min<std::size_t>(2 * n, 32);
    }
  }
  EXPECT_GT(lines, 10000u);
  EXPECT_GT(hidden, lines / 10);  // both answers well represented
  EXPECT_LT(hidden, lines - lines / 10);
  EXPECT_GT(only_by_candidate, 1000u);
  EXPECT_GT(candidates, 3000u);
  // Candidates that cross a line in plan but lie in none of its cells (see the next test): a
  // few here, near the origin.
  EXPECT_GT(crossing_elsewhere, 0u);
}

TEST(FanCandidates, AnEdgeThatRoundsToACrossingBeyondTheLineDoesNotBlockIt) {
  // Near the origin, an edge on the line through the eye and the target but 30-110 m beyond
  // the target (its points are s * target, s from 1.23 to 1.84, rounded): crossing_parameter's
  // rounding makes it a crossing at the target (1), but the line's walk never reaches its
  // cells, so line by line it cannot block. A fan along the same line 2.5 times as far holds
  // the edge as a candidate; blocked_among must still say the line is clear.
  const PlanePoint eye{0.0, 0.0};
  const PlanePoint t{-0x1.4262a10c34234p+5, 0x1.152c5fdbb0685p+7};
  const PlanePoint a{-0x1.04eaddb2d63a4p+6, 0x1.c0a6d9ab7ea8ap+7};
  const PlanePoint b{-0x1.7dc6b01792ab1p+6, 0x1.483c2fca347cp+8};
  ASSERT_EQ(sd::crossing_parameter(sd::PlanLine(eye, t), a, b), 1.0);  // the premise
  const std::vector<rp::ObstacleEdge> edges{edge(a.x, a.y, b.x, b.y)};
  const sd::EdgeGrid grid(edges);
  EXPECT_TRUE(offered(grid, eye, t).empty());
  sd::Fan fan;
  fan.reset(eye, {t, {2.5 * t.x, 2.5 * t.y}});
  const auto ends = [&](std::uint32_t i) { return std::pair{edges[i].a, edges[i].b}; };
  std::vector<sd::CandidateEdge> candidates;
  sd::fan_candidates(grid, fan, ends, candidates);
  ASSERT_EQ(candidates.size(), 1u);
  EXPECT_EQ(candidates[0].id, 0u);
  const auto crosses = [&](std::uint32_t i) {
    return !std::isnan(sd::crossing_parameter(sd::PlanLine(eye, t), edges[i].a, edges[i].b));
  };
  const auto by_id = [](const auto& test) {
    return [&test](const sd::CandidateEdge& c) { return test(c.id); };
  };
  EXPECT_FALSE(sd::blocked_among(candidates, eye, t, by_id(crosses)));
  EXPECT_FALSE(grid.any_along(eye, t, crosses));
  // The line to the fan's far end passes through the edge's cells: there it counts.
  const PlanePoint far{2.5 * t.x, 2.5 * t.y};
  const auto crosses_far = [&](std::uint32_t i) {
    return !std::isnan(sd::crossing_parameter(sd::PlanLine(eye, far), edges[i].a, edges[i].b));
  };
  EXPECT_EQ(sd::blocked_among(candidates, eye, far, by_id(crosses_far)),
            grid.any_along(eye, far, crosses_far));
}

TEST(OpenToBoth, NoLineFromEitherKerbCrossesAnEdgeWhenOpen) {
  // Random roads (straight or curved) with a kerb on each side (sometimes one on the road's
  // own line) and a few edges near lines from either kerb: anywhere near, 0-5 mm beside a
  // line, on the line through a kerb and a position (beyond its ends), across a line. When
  // open_to_both says open, the walk of every line from either kerb to a position (every 5 m)
  // or to a random point of the road offers no edge that crosses it in plan: no obstacle can
  // block it, which is what lets the sight stage skip the search. (A left fan whose hull leaves
  // out the right kerb fails here; dropping the right fan's own check does not: that check is
  // the Fan's rounding guard for the right kerb, which random edges do not reach.)
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> u(-1.0, 1.0), unit(0.0, 1.0);
  std::size_t open = 0, closed = 0, open_with_grazing = 0, lines = 0;
  for (int k = 0; k < 6000; ++k) {
    TestPath path;
    const PlanePoint start{731232.0 + 500 * u(rng), 4849872.0 + 500 * u(rng)};
    double heading = 3.2 * u(rng);
    const double turn = k % 3 == 0 ? 0.0 : 0.1 * u(rng);
    PlanePoint p = start;
    path.points.push_back(p), path.at_m.push_back(0.0);
    for (int j = 0; j < 8; ++j) {
      const double leg = 10 + 30 * unit(rng);
      p = {p.x + leg * std::cos(heading), p.y + leg * std::sin(heading)};
      path.points.push_back(p), path.at_m.push_back(path.at_m.back() + leg);
      heading += turn;
    }
    const double h0 = std::atan2(path.points[1].y - start.y, path.points[1].x - start.x);
    const double half_width = k % 7 == 0 ? 0.0 : 1 + 4 * unit(rng);  // 0: a kerb on the line
    const PlanePoint left{start.x - half_width * std::sin(h0), start.y + half_width * std::cos(h0)};
    const PlanePoint right{start.x + 3 * std::sin(h0), start.y - 3 * std::cos(h0)};
    const double end_m = path.at_m.back();
    std::vector<rp::ObstacleEdge> edges;
    bool grazing = false;
    for (int e = 0, n = k % 4; e < n; ++e) {
      const PlanePoint& eye = unit(rng) < 0.5 ? left : right;
      const PlanePoint t = path.at(end_m * unit(rng));
      const double along = 1.2 * unit(rng);
      const PlanePoint on{eye.x + along * (t.x - eye.x), eye.y + along * (t.y - eye.y)};
      const double len = std::hypot(t.x - eye.x, t.y - eye.y);
      const double nx = -(t.y - eye.y) / len, ny = (t.x - eye.x) / len;
      PlanePoint a, b;
      switch (e % 4) {
        case 0:  // anywhere near, mostly well off the road
          a = {on.x + 60 * u(rng), on.y + 60 * u(rng)};
          b = {a.x + 10 * u(rng), a.y + 10 * u(rng)};
          break;
        case 1: {  // an end 0-5 mm beside the line, pointing away from it
          const double off = 0.005 * u(rng);
          a = {on.x + off * nx, on.y + off * ny};
          const double away = off < 0 ? -1.0 : 1.0;
          b = {a.x + 5 * away * nx, a.y + 5 * away * ny};
          grazing = true;
          break;
        }
        case 2: {  // on the line through the kerb and a position, beyond either end
          const double s = unit(rng) < 0.5 ? -0.5 * unit(rng) : 1.0 + 0.5 * unit(rng);
          const double s2 = s + (s < 0 ? -0.2 : 0.2) * unit(rng);
          a = {eye.x + s * (t.x - eye.x), eye.y + s * (t.y - eye.y)};
          b = {eye.x + s2 * (t.x - eye.x), eye.y + s2 * (t.y - eye.y)};
          grazing = true;
          break;
        }
        default: {  // across the line
          const double l = 2 * unit(rng);
          a = {on.x - l * nx, on.y - l * ny}, b = {on.x + l * nx, on.y + l * ny};
          break;
        }
      }
      edges.push_back(edge(a.x, a.y, b.x, b.y));
    }
    const sd::EdgeGrid grid(edges);
    const auto ends = [&](std::uint32_t i) { return std::pair{edges[i].a, edges[i].b}; };
    sd::Fan from_left, from_right;
    std::vector<PlanePoint> outline = path.outline(0.0, end_m);
    if (!sd::open_to_both(grid, from_left, from_right, left, right, outline, ends)) {
      ++closed;
      continue;
    }
    ++open;
    open_with_grazing += grazing ? 1 : 0;
    std::vector<double> positions;
    for (double d = 0.0; d < end_m; d += 5.0) positions.push_back(d);
    positions.push_back(end_m);
    for (int j = 0; j < 20; ++j) positions.push_back(end_m * unit(rng));
    for (const PlanePoint& eye : {left, right}) {
      for (const double d : positions) {
        const PlanePoint target = path.at(d);
        const bool crossed = grid.any_along(eye, target, [&](std::uint32_t i) {
          return !std::isnan(
              sd::crossing_parameter(sd::PlanLine(eye, target), edges[i].a, edges[i].b));
        });
        ASSERT_FALSE(crossed) << k << " " << d;
        ++lines;
      }
    }
  }
  EXPECT_GT(open, 2000u);  // both answers well represented
  EXPECT_GT(closed, 2000u);
  EXPECT_GT(open_with_grazing, 100u);  // edges a few mm from a line, or on its line, were open
  EXPECT_GT(lines, 50000u);
}

TEST(FanCandidates, CrossingTermsFromTheEyeGiveTheCrossingParameterBitForBit) {
  // crossing_parameter(rx, ry, edge_from_eye(eye, a, b)), as a fan's candidates use it, against
  // crossing_parameter(PlanLine(eye, target), a, b) and the division form: random edges near
  // random lines (and ends on the line), in UTM coordinates.
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::size_t crossings = 0;
  for (int k = 0; k < 200000; ++k) {
    const PlanePoint eye{731232.0 + 500 * u(rng), 4849872.0 + 500 * u(rng)};
    const PlanePoint t{eye.x + 100 * u(rng), eye.y + 100 * u(rng)};
    const double s = k % 4 == 0 ? 1.0 : u(rng);
    const PlanePoint on{eye.x + s * (t.x - eye.x), eye.y + s * (t.y - eye.y)};
    const PlanePoint a{on.x + 5 * u(rng), on.y + 5 * u(rng)};
    const PlanePoint b = k % 3 == 0 ? on : PlanePoint{on.x + 5 * u(rng), on.y + 5 * u(rng)};
    const sd::PlanLine line(eye, t);
    const double want = sd::crossing_parameter(line, a, b);
    const double got = sd::crossing_parameter(line.rx, line.ry, sd::edge_from_eye(eye, a, b));
    const double division = reference_crossing(eye, t, a, b);
    ASSERT_EQ(std::isnan(got), std::isnan(want)) << k;
    ASSERT_EQ(std::isnan(got), std::isnan(division)) << k;
    if (!std::isnan(got)) {
      ASSERT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(want)) << k;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(got), std::bit_cast<std::uint64_t>(division)) << k;
      ++crossings;
    }
  }
  EXPECT_GT(crossings, 20000u);
}
