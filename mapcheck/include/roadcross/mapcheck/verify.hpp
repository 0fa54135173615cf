// `roadcross verify`: is a map file whole and the map its map_id names? For a map copied to a
// robot, before it is installed (docs/embedding.md, "Shipping a map").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace roadcross::mapcheck {

struct VerifyResult {
  /// One sentence per problem found, each naming the table, column, row or check; empty when
  /// the map passed every check.
  std::vector<std::string> problems;
  /// map_id as stored in the map's metadata (empty when absent) and as recomputed.
  std::string stored_map_id;
  std::string computed_map_id;
  std::int64_t segment_count = 0;
  bool ok() const noexcept { return problems.empty(); }
};

/// Checks the map at `path`, read only: SQLite's integrity_check; the GeoPackage application id,
/// the roadcross schema version and the segments' and crossings' columns against the schema;
/// every segment and crossing against its R*Tree box (and no box without a row); each column's
/// content digest and the map_id recomputed against the stored ones; and, when `expected_id` is
/// not empty, map_id against it. Never throws: a file that cannot be read is a problem too.
VerifyResult verify_map(const std::string& path, const std::string& expected_id = "");

}  // namespace roadcross::mapcheck
