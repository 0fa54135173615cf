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
#include <random>
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
  // Not mkstemp: the interrupt handler must know the name before the file exists (a signal
  // between creating and registering it would leave a file behind), so the name is chosen and
  // registered first, then created exclusively.
  std::random_device entropy;
  constexpr char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string candidate = target_ + ".tmp-";
    for (int i = 0; i < 6; ++i) candidate += kLetters[entropy() % (sizeof kLetters - 1)];
    set_interrupt_cleanup_path(candidate.c_str());
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd >= 0) {
      ::close(fd);
      temp_path_ = std::move(candidate);
      return;
    }
    set_interrupt_cleanup_path(nullptr);
    if (errno != EEXIST) {
      throw OutputError(target_ + ": cannot create the output (temporary file " + candidate +
                        "): " + std::strerror(errno));
    }
  }
  throw OutputError(target_ + ": cannot create the output: 100 temporary names taken");
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::remove(temp_path_.c_str());
    std::remove((temp_path_ + "-journal").c_str());
  }
  // Only now: a signal before this line removes what is already gone, which is harmless.
  set_interrupt_cleanup_path(nullptr);
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

void bind_maybe(sqlite::Statement& insert, int index, MaybeInt value) {
  insert.bind(index, value.optional());
}

void bind_maybe(sqlite::Statement& insert, int index, MaybeFloat value) {
  // Written as the float's exact value, so that a value reads back the same from the DB.
  insert.bind(index, value ? std::optional<double>(*value) : std::nullopt);
}

/// A text that may be absent (nullptr).
void bind_text(sqlite::Statement& insert, int index, const char* text) {
  if (text) {
    insert.bind(index, std::string_view(text));
  } else {
    insert.bind_null(index);
  }
}

void bind_segment(sqlite::Statement& insert, const RoadGraph& graph, const Segment& s,
                  std::int32_t srs_id) {
  int i = 1;
  insert.bind(i++, s.id);
  insert.bind(i++, std::span<const std::uint8_t>(schema::encode_linestring(graph.line(s), srs_id)));
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
  bind_maybe(insert, i++, s.class_cost);
  bind_maybe(insert, i++, s.junction_distance_m);
  bind_maybe(insert, i++, s.radius_m);
  bind_maybe(insert, i++, s.curvature_level);
  bind_maybe(insert, i++, s.curvature_cost);
  bind_maybe(insert, i++, s.elevation_m);
  bind_maybe(insert, i++, s.slope_deg);
  bind_maybe(insert, i++, s.grade_percent);
  bind_maybe(insert, i++, s.tpi_small_m);
  bind_maybe(insert, i++, s.tpi_large_m);
  bind_text(insert, i++, s.landform.text());
  bind_maybe(insert, i++, s.elevation_cost);
  bind_maybe(insert, i++, s.maxspeed_kmh);
  bind_maybe(insert, i++, s.lanes);
  bind_maybe(insert, i++, s.width_m);
  bind_maybe(insert, i++, s.context_score);
  bind_maybe(insert, i++, s.crossing_distance_m);
  bind_text(insert, i++, s.context_defaulted ? s.context_defaulted->c_str() : nullptr);
  bind_text(insert, i++, s.override_note ? s.override_note->c_str() : nullptr);
  insert.bind(i++, int{s.override_no_crossing});
  insert.bind(i++, int{s.override_force_suitable});
  bind_maybe(insert, i++, s.rank);
  bind_maybe(insert, i++, s.score);
  insert.bind(i++, s.reasons.joined(','));
  bind_maybe(insert, i++, s.sight_forward_m);
  bind_maybe(insert, i++, s.sight_backward_m);
  bind_maybe(insert, i++, s.sight_min_m);
  bind_maybe(insert, i++, s.required_sight_m);
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
    bind_segment(insert, graph, s, srs_id);
    insert.run();
    const schema::Envelope e = schema::envelope_of(graph.line(s));
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
  for (const Segment& s : graph.segments)
    entries.push_back({s.id, schema::envelope_of(graph.line(s))});
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
    // A 64 MiB page cache: rows arrive in rowid order and the R*Tree is bulk-loaded, so a
    // larger cache only adds to the peak memory (256 MiB cost 190 MB more at 50x Monaco for
    // the same writing time).
    db.exec("PRAGMA cache_size = -65536");
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
