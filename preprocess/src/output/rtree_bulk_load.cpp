#include "roadcross/preprocess/output/rtree_bulk_load.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

#include "roadcross/preprocess/output/bulk_insert.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross::preprocess {
namespace {

using EntryAt = std::function<RtreeEntry(std::size_t)>;

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

/// The entries in Hilbert order of their boxes' centres, ties by id, as (key << 32 | index)
/// values: 8 bytes an entry, sorted as plain integers. The key is the position on a curve over
/// a 2^16 x 2^16 grid, so it fits 32 bits; entry ids ascend with the index, so ordering ties by
/// index orders them by id. The boxes themselves are not held: a leaf's cells are computed
/// again from `entry_at` when the leaf is written.
std::vector<std::uint64_t> entries_along_hilbert_curve(std::size_t count, const EntryAt& entry_at) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  std::int64_t previous_id = std::numeric_limits<std::int64_t>::min();
  for (std::size_t i = 0; i < count; ++i) {
    const RtreeEntry e = entry_at(i);
    if (e.id <= previous_id) {
      throw std::invalid_argument("bulk_load_rtree: entry ids must ascend with the index");
    }
    previous_id = e.id;
    min_x = std::min(min_x, e.box.min_x);
    min_y = std::min(min_y, e.box.min_y);
    max_x = std::max(max_x, e.box.max_x);
    max_y = std::max(max_y, e.box.max_y);
  }
  const double scale = 65535.0 / std::max({max_x - min_x, max_y - min_y, 1e-9});
  std::vector<std::uint64_t> keyed(count);
  for (std::size_t i = 0; i < count; ++i) {
    const schema::Envelope b = entry_at(i).box;
    const auto cx = static_cast<std::uint32_t>((0.5 * (b.min_x + b.max_x) - min_x) * scale);
    const auto cy = static_cast<std::uint32_t>((0.5 * (b.min_y + b.max_y) - min_y) * scale);
    keyed[i] = hilbert_index(cx, cy) << 32 | i;
  }
  std::sort(keyed.begin(), keyed.end());
  return keyed;
}

/// The index of the entry in a value of entries_along_hilbert_curve().
std::size_t entry_index(std::uint64_t keyed) {
  return keyed & 0xffffffffu;
}

Cell leaf_cell(const RtreeEntry& e) {
  const schema::Envelope& b = e.box;
  return {e.id, round_down(b.min_x), round_up(b.max_x), round_down(b.min_y), round_up(b.max_y)};
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

/// The _rowid table's rows: (entry id, its leaf node) in index order, which is id order, so
/// every row is an append to the table's last page. (The leaves hold the entries in Hilbert
/// order, random in id: in that order every row would be a B-tree search and a page split.)
class RowidRows final : public RowSource {
 public:
  RowidRows(const std::vector<std::uint32_t>& leaf_of_entry, const EntryAt& entry_at)
      : leaf_of_entry_(leaf_of_entry), entry_at_(entry_at) {}
  std::size_t row_count() const override { return leaf_of_entry_.size(); }
  int column_count() const override { return 2; }
  std::optional<std::int64_t> ascending_rowid(std::size_t row) const override {
    return entry_at_(row).id;
  }
  void column(std::size_t row, int /*column 1*/, sqlite3_context* out) const override {
    sqlite3_result_int64(out, leaf_of_entry_[row]);
  }

 private:
  const std::vector<std::uint32_t>& leaf_of_entry_;
  const EntryAt& entry_at_;
};

/// Writes one tree's nodes into <name>_node and its child -> parent rows into <name>_parent.
class NodeWriter {
 public:
  NodeWriter(sqlite3* db, const std::string& rtree_name, std::size_t node_size)
      : put_node_(db, "INSERT OR REPLACE INTO \"" + rtree_name + "_node\" VALUES (?, ?)"),
        put_parent_(db, "INSERT INTO \"" + rtree_name + "_parent\" VALUES (?, ?)"),
        node_size_(node_size) {}

  std::size_t fanout() const { return (node_size_ - 4) / kBytesPerCell; }

  /// Writes node `node` holding `cells`; `depth_if_root` is the tree's depth for the root
  /// (node 1), 0 for the others.
  void node(std::int64_t node, const Cell* cells, std::size_t count, int depth_if_root) {
    put_node_.bind(1, node);
    const auto blob = node_blob(cells, count, node_size_, depth_if_root);
    put_node_.bind(2, std::span<const std::uint8_t>(blob));
    put_node_.run();
  }

  void parent(std::int64_t child, std::int64_t parent) {
    put_parent_.bind(1, child);
    put_parent_.bind(2, parent);
    put_parent_.run();
  }

 private:
  sqlite::Statement put_node_, put_parent_;
  std::size_t node_size_;
};

/// One level of nodes being built: their bounding cells (the cells of the level above) and
/// node numbers.
struct Level {
  std::vector<Cell> cells;
  std::vector<std::int64_t> nodes;
};

/// Writes the leaves, `fanout` consecutive entries along the curve each, numbered from
/// `next_node` on (node 1 if one leaf holds all), and records each entry's leaf by its index.
Level write_leaves(NodeWriter& out, const std::vector<std::uint64_t>& order,
                   const EntryAt& entry_at, std::int64_t& next_node,
                   std::vector<std::uint32_t>& leaf_of_entry) {
  const std::size_t fanout = out.fanout();
  const bool is_root = order.size() <= fanout;
  Level leaves;
  std::vector<Cell> cells;
  for (std::size_t start = 0; start < order.size(); start += fanout) {
    const std::size_t in_node = std::min(fanout, order.size() - start);
    const std::int64_t node = is_root ? 1 : next_node++;
    cells.clear();
    for (std::size_t i = start; i < start + in_node; ++i) {
      const std::size_t index = entry_index(order[i]);
      cells.push_back(leaf_cell(entry_at(index)));
      leaf_of_entry[index] = static_cast<std::uint32_t>(node);
    }
    out.node(node, cells.data(), in_node, 0);
    leaves.cells.push_back(bounding_cell(cells.data(), in_node, node));
    leaves.nodes.push_back(node);
  }
  return leaves;
}

/// Writes the inner nodes above `level` (two or more nodes), from depth 1 up to the root,
/// node 1.
void write_inner_levels(NodeWriter& out, Level level, std::int64_t next_node) {
  const std::size_t fanout = out.fanout();
  for (int depth = 1;; ++depth) {
    const bool is_root_level = level.cells.size() <= fanout;
    Level parents;
    for (std::size_t start = 0; start < level.cells.size(); start += fanout) {
      const std::size_t in_node = std::min(fanout, level.cells.size() - start);
      const std::int64_t node = is_root_level ? 1 : next_node++;
      out.node(node, &level.cells[start], in_node, is_root_level ? depth : 0);
      // Child node numbers grow along the level: these rows are appended in key order.
      for (std::size_t i = start; i < start + in_node; ++i) out.parent(level.nodes[i], node);
      parents.cells.push_back(bounding_cell(&level.cells[start], in_node, node));
      parents.nodes.push_back(node);
    }
    if (is_root_level) return;
    level = std::move(parents);
  }
}

}  // namespace

void bulk_load_rtree(sqlite3* db, const std::string& rtree_name,
                     const std::vector<RtreeEntry>& entries) {
  bulk_load_rtree(db, rtree_name, entries.size(), [&](std::size_t i) { return entries[i]; });
}

void bulk_load_rtree(sqlite3* db, const std::string& rtree_name, std::size_t count,
                     const EntryAt& entry_at) {
  if (count == 0) return;
  if (count > std::numeric_limits<std::uint32_t>::max()) {
    throw std::length_error("bulk_load_rtree: more than 2^32 - 1 entries");
  }
  sqlite::Statement size_query(
      db, "SELECT length(data) FROM \"" + rtree_name + "_node\" WHERE nodeno = 1");
  if (!size_query.step()) throw sqlite::sqlite_error(SQLITE_CORRUPT, rtree_name + ": no root node");
  NodeWriter out(db, rtree_name, static_cast<std::size_t>(size_query.column_int64(0)));

  // Built bottom-up: each level's cells packed into full nodes; node numbers 2, 3, ... go to
  // the nodes of all levels below the root, and the single top node becomes the root, node 1.
  std::int64_t next_node = 2;
  std::vector<std::uint32_t> leaf_of_entry(count);
  Level leaves;
  {  // the order along the curve is freed before the _rowid rows are written
    const std::vector<std::uint64_t> order = entries_along_hilbert_curve(count, entry_at);
    leaves = write_leaves(out, order, entry_at, next_node, leaf_of_entry);
  }
  insert_rows(db, rtree_name + "_rowid", "rowid, nodeno", RowidRows(leaf_of_entry, entry_at));
  if (leaves.nodes.size() > 1) write_inner_levels(out, std::move(leaves), next_node);
}

}  // namespace roadcross::preprocess
