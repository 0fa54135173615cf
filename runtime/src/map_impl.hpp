// The inside of roadcross::Map, shared by the runtime's translation units (map.cpp for opening
// and geometry queries, assess.cpp for the cost terms). Not installed.
#pragma once

#include <string>
#include <vector>

#include "roadcross/runtime.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross {

namespace detail {

/// Prepared once per Map, reused by every query (SQLite's advice for hot paths).
struct Queries {
  sqlite::Statement candidates;  ///< segments whose R*Tree box meets a query box
  sqlite::Statement attributes;  ///< identity of one segment
  sqlite::Statement cost_terms;  ///< every cost column of one segment

  explicit Queries(sqlite::Database& db);
};

/// Suitability thresholds as recorded by the build (param.suitability.*), else DESIGN.md's.
struct Thresholds {
  double valid_distance_m = 10.0;
  double threshold = 20.0;
};

Thresholds thresholds_from(const MapInfo& info);

}  // namespace detail

struct Map::Impl {
  sqlite::Database db;
  MapInfo info;
  detail::Queries queries;
  detail::Thresholds thresholds;
  std::vector<schema::PlanePoint> scratch;  // reused geometry buffer: no allocation per query
  std::vector<schema::PlanePoint> best_geometry;

  Impl(sqlite::Database&& database, MapInfo&& map_info)
      : db(std::move(database)),
        info(std::move(map_info)),
        queries(db),
        thresholds(detail::thresholds_from(info)) {}
};

}  // namespace roadcross
