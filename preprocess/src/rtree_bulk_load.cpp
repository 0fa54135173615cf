#include "roadcross/preprocess/rtree_bulk_load.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <utility>

#include "roadcross/preprocess/bulk_insert.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross::preprocess {
namespace {

constexpr std::size_t kBytesPerCell = 8 + 4 * 4;  // 64-bit id + 4 float32 coordinates

/// Position of (x, y) along a Hilbert curve over a 2^16 x 2^16 grid.
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y) {
  std::uint64_t index = 0;
  for (std::uint32_t s = 1u << 15; s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    index += std::uint64_t{s} * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return index;
}

// SQLite stores coordinates as float32 rounded outwards, so that a box never shrinks. These
// are rtree.c's rtreeValueDown/rtreeValueUp, so the tree holds the same values an INSERT would.
constexpr double kRoundTowards = 1.0 - 1.0 / 8388608.0;
constexpr double kRoundAway = 1.0 + 1.0 / 8388608.0;
float round_down(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) > value)
    f = static_cast<float>(value * (value < 0 ? kRoundAway : kRoundTowards));
  return f;
}
float round_up(double value) {
  float f = static_cast<float>(value);
  if (static_cast<double>(f) < value)
    f = static_cast<float>(value * (value < 0 ? kRoundTowards : kRoundAway));
  return f;
}

void put_big_endian(std::uint8_t* out, std::uint64_t value, int bytes) {
  for (int i = bytes - 1; i >= 0; --i) {
    out[i] = static_cast<std::uint8_t>(value & 0xff);
    value >>= 8;
  }
}

void put_coordinate(std::uint8_t* out, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  put_big_endian(out, bits, 4);
}

struct Cell {
  std::int64_t id;  // entry id in a leaf, child node number in an inner node
  float min_x, max_x, min_y, max_y;
};

/// The leaf cells in Hilbert order of their boxes' centres (ties by id), built from `count`
/// entries read twice through `entry_at`: the boxes are held as float cells (24 bytes an
/// entry) with an 8-byte key, not as double boxes.
std::vector<Cell> leaf_cells_along_hilbert_curve(
    std::size_t count, const std::function<RtreeEntry(std::size_t)>& entry_at) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (std::size_t i = 0; i < count; ++i) {
    const schema::Envelope b = entry_at(i).box;
    min_x = std::min(min_x, b.min_x);
    min_y = std::min(min_y, b.min_y);
    max_x = std::max(max_x, b.max_x);
    max_y = std::max(max_y, b.max_y);
  }
  const double scale = 65535.0 / std::max({max_x - min_x, max_y - min_y, 1e-9});
  struct KeyedCell {
    std::uint64_t key;
    Cell cell;
  };
  std::vector<KeyedCell> keyed(count);
  for (std::size_t i = 0; i < count; ++i) {
    const RtreeEntry e = entry_at(i);
    const schema::Envelope& b = e.box;
    const auto cx = static_cast<std::uint32_t>((0.5 * (b.min_x + b.max_x) - min_x) * scale);
    const auto cy = static_cast<std::uint32_t>((0.5 * (b.min_y + b.max_y) - min_y) * scale);
    keyed[i] = {
        hilbert_index(cx, cy),
        {e.id, round_down(b.min_x), round_up(b.max_x), round_down(b.min_y), round_up(b.max_y)}};
  }
  std::sort(keyed.begin(), keyed.end(), [](const KeyedCell& a, const KeyedCell& b) {
    return a.key != b.key ? a.key < b.key : a.cell.id < b.cell.id;
  });
  std::vector<Cell> cells;
  cells.reserve(count);
  for (const KeyedCell& k : keyed) cells.push_back(k.cell);
  return cells;
}

std::vector<std::uint8_t> node_blob(const Cell* cells, std::size_t count, std::size_t node_size,
                                    int depth_if_root) {
  std::vector<std::uint8_t> blob(node_size, 0);
  put_big_endian(blob.data(), static_cast<std::uint64_t>(depth_if_root), 2);
  put_big_endian(blob.data() + 2, count, 2);
  for (std::size_t i = 0; i < count; ++i) {
    std::uint8_t* cell = blob.data() + 4 + i * kBytesPerCell;
    put_big_endian(cell, static_cast<std::uint64_t>(cells[i].id), 8);
    put_coordinate(cell + 8, cells[i].min_x);
    put_coordinate(cell + 12, cells[i].max_x);
    put_coordinate(cell + 16, cells[i].min_y);
    put_coordinate(cell + 20, cells[i].max_y);
  }
  return blob;
}

Cell bounding_cell(const Cell* cells, std::size_t count, std::int64_t node_number) {
  Cell out{node_number, cells[0].min_x, cells[0].max_x, cells[0].min_y, cells[0].max_y};
  for (std::size_t i = 1; i < count; ++i) {
    out.min_x = std::min(out.min_x, cells[i].min_x);
    out.max_x = std::max(out.max_x, cells[i].max_x);
    out.min_y = std::min(out.min_y, cells[i].min_y);
    out.max_y = std::max(out.max_y, cells[i].max_y);
  }
  return out;
}

/// The _rowid table's rows: (entry id, its leaf node), sorted by id.
class RowidRows final : public RowSource {
 public:
  explicit RowidRows(const std::vector<std::pair<std::int64_t, std::int64_t>>& rows)
      : rows_(rows) {}
  std::size_t row_count() const override { return rows_.size(); }
  int column_count() const override { return 2; }
  void column(std::size_t row, int column, sqlite3_context* out) const override {
    sqlite3_result_int64(out, column == 0 ? rows_[row].first : rows_[row].second);
  }

 private:
  const std::vector<std::pair<std::int64_t, std::int64_t>>& rows_;
};

/// The _rowid table maps each entry id to its leaf node. The leaves hold the entries in Hilbert
/// order, which is random in id: inserted in that order, every row is a B-tree search and a
/// page split in the middle of the table; sorted by id first, every row is an append to the
/// table's last page.
void insert_rowid_rows(sqlite3* db, const std::string& rowid_table,
                       std::vector<std::pair<std::int64_t, std::int64_t>>& leaf_of_entry) {
  std::sort(leaf_of_entry.begin(), leaf_of_entry.end());
  insert_rows(db, rowid_table, "rowid, nodeno", RowidRows(leaf_of_entry));
  leaf_of_entry.clear();
  leaf_of_entry.shrink_to_fit();
}

}  // namespace

void bulk_load_rtree(sqlite3* db, const std::string& rtree_name,
                     const std::vector<RtreeEntry>& entries) {
  bulk_load_rtree(db, rtree_name, entries.size(), [&](std::size_t i) { return entries[i]; });
}

void bulk_load_rtree(sqlite3* db, const std::string& rtree_name, std::size_t count,
                     const std::function<RtreeEntry(std::size_t)>& entry_at) {
  if (count == 0) return;
  const std::string quoted = "\"" + rtree_name;
  sqlite::Statement size_query(db,
                               "SELECT length(data) FROM " + quoted + "_node\" WHERE nodeno = 1");
  if (!size_query.step()) throw sqlite::sqlite_error(SQLITE_CORRUPT, rtree_name + ": no root node");
  const auto node_size = static_cast<std::size_t>(size_query.column_int64(0));
  const std::size_t fanout = (node_size - 4) / kBytesPerCell;

  sqlite::Statement put_node(db, "INSERT OR REPLACE INTO " + quoted + "_node\" VALUES (?, ?)");
  sqlite::Statement put_parent(db, "INSERT INTO " + quoted + "_parent\" VALUES (?, ?)");

  std::vector<Cell> level = leaf_cells_along_hilbert_curve(count, entry_at);
  // Build bottom-up: pack each level's cells into full nodes; node numbers 2, 3, ... go to the
  // nodes of all levels below the root, and the single top node becomes the root, number 1.
  std::int64_t next_node = 2;
  int depth = 0;
  std::vector<std::int64_t> child_nodes;  // node numbers of `level`'s cells (inner levels)
  std::vector<std::pair<std::int64_t, std::int64_t>> leaf_of_entry;  // (entry id, leaf node)
  leaf_of_entry.reserve(count);
  while (true) {
    const bool is_root_level = level.size() <= fanout;
    std::vector<Cell> parents;
    std::vector<std::int64_t> parent_nodes;
    for (std::size_t start = 0; start < level.size(); start += fanout) {
      const std::size_t in_node = std::min(fanout, level.size() - start);
      const std::int64_t node = is_root_level ? 1 : next_node++;
      put_node.bind(1, node);
      const auto blob = node_blob(&level[start], in_node, node_size, is_root_level ? depth : 0);
      put_node.bind(2, std::span<const std::uint8_t>(blob));
      put_node.run();
      for (std::size_t i = start; i < start + in_node; ++i) {
        if (depth == 0) {
          leaf_of_entry.emplace_back(level[i].id, node);
        } else {
          // Child node numbers grow along the level: these rows are appended in key order.
          put_parent.bind(1, child_nodes[i]);
          put_parent.bind(2, node);
          put_parent.run();
        }
      }
      parents.push_back(bounding_cell(&level[start], in_node, node));
      parent_nodes.push_back(node);
    }
    if (depth == 0) insert_rowid_rows(db, rtree_name + "_rowid", leaf_of_entry);
    if (is_root_level) break;
    level.swap(parents);
    child_nodes.swap(parent_nodes);
    ++depth;
  }
}

}  // namespace roadcross::preprocess
