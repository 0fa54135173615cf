#include "roadcross/preprocess/gpkg_writer.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

#include "roadcross/preprocess/errors.hpp"
#include "roadcross/preprocess/interrupt.hpp"
#include "roadcross/preprocess/progress.hpp"
#include "roadcross/preprocess/rtree_bulk_load.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace roadcross::preprocess {

AtomicOutput::AtomicOutput(std::string target) : target_(std::move(target)) {
  std::string pattern = target_ + ".tmp-XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) {
    throw OutputError(target_ + ": cannot create the output (temporary file " + pattern +
                      "): " + std::strerror(errno));
  }
  ::close(fd);
  temp_path_ = pattern;
  set_interrupt_cleanup_path(temp_path_.c_str());
}

AtomicOutput::~AtomicOutput() {
  set_interrupt_cleanup_path(nullptr);
  if (!committed_) {
    std::remove(temp_path_.c_str());
    std::remove((temp_path_ + "-journal").c_str());
  }
}

void AtomicOutput::commit() {
  // mkstemp creates 0600; a map is meant to be shared like any other output file.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::chmod(temp_path_.c_str(), 0666 & ~mask);
  if (std::rename(temp_path_.c_str(), target_.c_str()) != 0) {
    throw OutputError(target_ +
                      ": cannot move the finished output into place: " + std::strerror(errno));
  }
  committed_ = true;
  set_interrupt_cleanup_path(nullptr);
}

namespace {

std::string join(const std::vector<std::string>& items, char separator) {
  std::string out;
  for (const std::string& item : items) {
    if (!out.empty()) out += separator;
    out += item;
  }
  return out;
}

void bind_segment(sqlite::Statement& insert, const Segment& s, std::int32_t srs_id) {
  int i = 1;
  insert.bind(i++, s.id);
  insert.bind(i++, std::span<const std::uint8_t>(schema::encode_linestring(s.points, srs_id)));
  insert.bind(i++, s.osm_way_id);
  insert.bind(i++, s.highway);
  if (s.name.empty()) {
    insert.bind_null(i++);
  } else {
    insert.bind(i++, s.name);
  }
  insert.bind(i++, s.length_m);
  insert.bind(i++, s.from_node_id);
  insert.bind(i++, s.to_node_id);
  insert.bind(i++, int{s.oneway});
  insert.bind(i++, int{s.tunnel});
  insert.bind(i++, int{s.bridge});
  insert.bind(i++, s.class_cost);
  insert.bind(i++, s.junction_distance_m);
  insert.bind(i++, s.radius_m);
  insert.bind(i++, s.curvature_level);
  insert.bind(i++, s.curvature_cost);
  insert.bind(i++, s.elevation_m);
  insert.bind(i++, s.slope_deg);
  insert.bind(i++, s.grade_percent);
  insert.bind(i++, s.tpi_small_m);
  insert.bind(i++, s.tpi_large_m);
  insert.bind(i++, s.landform);
  insert.bind(i++, s.elevation_cost);
  insert.bind(i++, s.maxspeed_kmh);
  insert.bind(i++, s.lanes);
  insert.bind(i++, s.width_m);
  insert.bind(i++, s.context_score);
  insert.bind(i++, s.crossing_distance_m);
  insert.bind(i++, s.context_defaulted);
  insert.bind(i++, s.override_note);
  insert.bind(i++, int{s.override_no_crossing});
  insert.bind(i++, int{s.override_force_suitable});
  insert.bind(i++, s.rank);
  insert.bind(i++, s.score);
  if (s.reasons.empty()) {
    insert.bind(i++, std::string_view(""));
  } else {
    insert.bind(i++, join(s.reasons, ','));
  }
  // The column list lives in schema/; a field added there but not here must fail loudly.
  if (i - 1 != insert.parameter_count()) {
    throw std::logic_error("segments insert binds " + std::to_string(i - 1) + " values for " +
                           std::to_string(insert.parameter_count()) + " columns");
  }
}

std::string insert_segment_sql() {
  std::string names = "fid, geom", params = "?, ?";
  for (const schema::Column& column : schema::segment_columns()) {
    names += ", " + std::string(column.name);
    params += ", ?";
  }
  return "INSERT INTO " + std::string(schema::kSegmentsTable) + " (" + names + ") VALUES (" +
         params + ")";
}

/// Inserts every segment row; returns the extent of all segments.
schema::Envelope write_segment_rows(sqlite::Database& db, const RoadGraph& graph,
                                    Progress& progress) {
  const std::int32_t srs_id = graph.zone.epsg();
  sqlite::Statement insert = db.prepare(insert_segment_sql());
  schema::Envelope extent{
      std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
      std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  std::size_t written = 0;
  for (const Segment& s : graph.segments) {
    bind_segment(insert, s, srs_id);
    insert.run();
    const schema::Envelope e = schema::envelope_of(s.points);
    extent.min_x = std::min(extent.min_x, e.min_x);
    extent.max_x = std::max(extent.max_x, e.max_x);
    extent.min_y = std::min(extent.min_y, e.min_y);
    extent.max_y = std::max(extent.max_y, e.max_y);
    if (++written % 4096 == 0) progress.update(written, graph.segments.size());
  }
  return extent;
}

/// Fills the R*Tree with every segment's bounding box (bulk load: see rtree_bulk_load.hpp).
void write_segment_rtree(sqlite::Database& db, const RoadGraph& graph) {
  std::vector<RtreeEntry> entries;
  entries.reserve(graph.segments.size());
  for (const Segment& s : graph.segments) entries.push_back({s.id, schema::envelope_of(s.points)});
  bulk_load_rtree(db.handle(), std::string(schema::kSegmentsRtree), entries);
}

/// Inserts the crossing points (fid 1..n in the given order) and fills their R*Tree; returns
/// their extent, or nullopt when there are none.
std::optional<schema::Envelope> write_crossings(sqlite::Database& db,
                                                const std::vector<Crossing>& crossings,
                                                std::int32_t srs_id) {
  std::string names = "fid, geom", params = "?, ?";
  for (const schema::Column& column : schema::crossing_columns()) {
    names += ", " + std::string(column.name);
    params += ", ?";
  }
  sqlite::Statement insert = db.prepare("INSERT INTO " + std::string(schema::kCrossingsTable) +
                                        " (" + names + ") VALUES (" + params + ")");
  std::vector<RtreeEntry> entries;
  std::int64_t fid = 0;
  for (const Crossing& c : crossings) {
    int i = 1;
    insert.bind(i++, ++fid);
    insert.bind(i++, std::span<const std::uint8_t>(schema::encode_point(c.point, srs_id)));
    insert.bind(i++, c.osm_id);
    insert.bind(i++, c.osm_type);
    insert.bind(i++, c.kind.type);
    insert.bind(i++, int{c.kind.signals});
    insert.bind(i++, int{c.kind.designated});
    insert.bind(i++, c.segment_id);
    if (i - 1 != insert.parameter_count()) throw std::logic_error("crossings insert: column count");
    insert.run();
    entries.push_back({fid, schema::Envelope{c.point.x, c.point.x, c.point.y, c.point.y}});
  }
  bulk_load_rtree(db.handle(), std::string(schema::kCrossingsRtree), entries);
  if (entries.empty()) return std::nullopt;
  schema::Envelope extent = entries.front().box;
  for (const RtreeEntry& e : entries) {
    extent.min_x = std::min(extent.min_x, e.box.min_x);
    extent.max_x = std::max(extent.max_x, e.box.max_x);
    extent.min_y = std::min(extent.min_y, e.box.min_y);
    extent.max_y = std::max(extent.max_y, e.box.max_y);
  }
  return extent;
}

}  // namespace

void write_geopackage(const std::string& path, const DatabaseContents& contents,
                      Progress& progress) {
  const RoadGraph& graph = *contents.graph;
  progress.start_stage("writing the GeoPackage", "segments");
  try {
    sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX);
    // The file is private until renamed into place, so durability tricks are unnecessary:
    // no journal, no fsync; a fixed page size keeps the bytes identical across runs.
    db.exec("PRAGMA page_size = 4096");
    db.exec("PRAGMA journal_mode = OFF");
    db.exec("PRAGMA synchronous = OFF");
    // The R*Tree and the table's B-tree stay in memory while they grow (256 MiB at most).
    db.exec("PRAGMA cache_size = -262144");
    db.exec("BEGIN");
    for (const std::string& statement :
         schema::create_statements(graph.zone.zone, graph.zone.northern, contents.last_change)) {
      db.exec(statement);
    }
    const schema::Envelope extent = write_segment_rows(db, graph, progress);
    write_segment_rtree(db, graph);
    auto update = db.prepare(
        "UPDATE gpkg_contents SET min_x = ?, min_y = ?, max_x = ?, max_y = ? WHERE table_name = "
        "?");
    const auto set_extent = [&](const schema::Envelope& e, std::string_view table) {
      update.bind(1, e.min_x);
      update.bind(2, e.min_y);
      update.bind(3, e.max_x);
      update.bind(4, e.max_y);
      update.bind(5, table);
      update.run();
    };
    set_extent(extent, schema::kSegmentsTable);
    if (contents.crossings) {
      const auto crossing_extent = write_crossings(db, *contents.crossings, graph.zone.epsg());
      if (crossing_extent) set_extent(*crossing_extent, schema::kCrossingsTable);
    }
    for (const std::string& statement : schema::rtree_trigger_statements()) db.exec(statement);

    auto insert_meta =
        db.prepare("INSERT INTO " + std::string(schema::kMetadataTable) + " VALUES (?, ?)");
    auto put = [&](std::string_view key, const std::string& value) {
      insert_meta.bind(1, key);
      insert_meta.bind(2, value);
      insert_meta.run();
    };
    put(schema::meta::kSchemaVersion, std::to_string(schema::kSchemaVersion));
    put(schema::meta::kUtmZone, std::to_string(graph.zone.zone));
    put(schema::meta::kUtmNorthern, graph.zone.northern ? "1" : "0");
    put(schema::meta::kEpsg, std::to_string(graph.zone.epsg()));
    put(schema::meta::kSegmentCount, std::to_string(graph.segments.size()));
    for (const auto& [key, value] : contents.metadata) put(key, value);
    db.exec("COMMIT");
  } catch (const sqlite::sqlite_error& e) {
    throw OutputError(std::string("cannot write the database: ") + e.what());
  }
  progress.finish_stage(std::to_string(graph.segments.size()) + " segments");
}

}  // namespace roadcross::preprocess
