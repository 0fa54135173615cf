// Bulk load of an SQLite R*Tree (the GeoPackage spatial index) by writing a packed Hilbert
// R-tree straight into the virtual table's shadow tables (<name>_node, _rowid, _parent).
// SQLite's own one-row-at-a-time insert rebalances the tree at every entry; this writes each
// node once and gives full, spatially tight nodes (docs/performance.md, "R*Tree bulk load"). GDAL's
// GPKG driver loads its R-trees the same way. The layout follows SQLite's ext/rtree/rtree.c and is
// verified with SQLite's own rtreecheck() in the tests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "roadcross/schema/gpkg_geometry.hpp"

struct sqlite3;

namespace roadcross::preprocess {

struct RtreeEntry {
  std::int64_t id = 0;
  schema::Envelope box;
};

/// Fills the empty 2-D R*Tree virtual table `rtree_name` (created with CREATE VIRTUAL TABLE ...
/// USING rtree(id, minx, maxx, miny, maxy) in `db`, nothing inserted yet) with `entries`, whose
/// ids must ascend (std::invalid_argument otherwise). Throws sqlite::sqlite_error on failure.
void bulk_load_rtree(sqlite3* db, const std::string& rtree_name,
                     const std::vector<RtreeEntry>& entries);

/// The same for `count` (< 2^32) entries produced by `entry_at(i)`, i < count, ids ascending
/// with i. `entry_at` is called four times per entry: the caller need not hold the entries
/// (40 bytes each), and the load holds 12 bytes an entry (its place on the curve and its leaf),
/// not the boxes: at the build's peak memory that matters more than the repeated calls.
void bulk_load_rtree(sqlite3* db, const std::string& rtree_name, std::size_t count,
                     const std::function<RtreeEntry(std::size_t)>& entry_at);

}  // namespace roadcross::preprocess
