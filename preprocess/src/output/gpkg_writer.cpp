#include "roadcross/preprocess/output/gpkg_writer.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "roadcross/files/atomic_file.hpp"
#include "roadcross/geo_box.hpp"
#include "roadcross/mapcheck/bulk_io_vfs.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/interrupt.hpp"
#include "roadcross/preprocess/common/progress.hpp"
#include "roadcross/preprocess/output/bulk_insert.hpp"
#include "roadcross/preprocess/output/qgis_styles.hpp"
#include "roadcross/preprocess/output/row_values.hpp"
#include "roadcross/preprocess/output/rtree_bulk_load.hpp"
#include "roadcross/schema/gpkg_geometry.hpp"
#include "roadcross/schema/schema.hpp"
#include "roadcross/schema/sqlite.hpp"
#include "roadcross/schema/verdict.hpp"

namespace roadcross::preprocess {

namespace {

/// files::AtomicFile throws std::runtime_error; the build reports output failures as OutputError.
template <typename Action>
auto as_output_error(Action&& action) {
  try {
    return action();
  } catch (const std::runtime_error& e) {
    throw OutputError(e.what());
  }
}

}  // namespace

AtomicOutput::AtomicOutput(const std::string& target)
    : file_(as_output_error([&] {
        return std::make_unique<files::AtomicFile>(target, set_interrupt_cleanup_path);
      })) {
  file_->remove_also("-journal");
  file_->remove_also(kSideRowsSuffix);
}

AtomicOutput::~AtomicOutput() = default;

void AtomicOutput::commit() {
  as_output_error([&] { file_->commit(); });
}

namespace {

template <typename Out>
void result(Out& out, MaybeInt value) {
  value ? out.integer(*value) : out.null();
}

template <typename Out>
void result(Out& out, MaybeFloat value) {
  // Written as the float's exact value, so that a value reads back the same from the DB.
  value ? out.real(static_cast<double>(*value)) : out.null();
}

template <typename Out>
void result(Out& out, bool value) {
  out.integer(value ? 1 : 0);
}

/// 1, 0, or NULL for unknown.
template <typename Out>
void optional_flag(Out& out, std::optional<bool> value) {
  value ? out.integer(*value ? 1 : 0) : out.null();
}

/// A text that may be absent (nullptr: NULL).
template <typename Out>
void lasting_text(Out& out, const std::string* text) {
  text ? out.lasting_text(*text) : out.null();
}

/// The segments table's rows: fid, geom, then schema::segment_columns() in order.
class SegmentRows final : public RowSource {
 public:
  /// fid, geom and every schema::SegmentColumn (the switch below names each one: the compiler
  /// warns about a column added to the schema but not written here).
  static constexpr int kColumns = 2 + static_cast<int>(schema::kSegmentColumnCount);

  /// Rows [first, last) of the graph's segments; `rule`: what the stored verdict is judged under.
  /// With `fed_digests`, column() hands SQLite the rows it digests: each value computed once
  /// for the file and its digests (the geometry's encoding, the reasons, the verdict).
  SegmentRows(const RoadGraph& graph, const SuitabilityRule& rule, std::size_t first,
              std::size_t last, FedRowDigests<kColumns>* fed_digests = nullptr)
      : graph_(graph),
        rule_(rule),
        first_(first),
        count_(last - first),
        srs_id_(graph.zone.epsg()),
        fed_digests_(fed_digests) {}
  std::size_t row_count() const override { return count_; }
  int column_count() const override { return kColumns; }

  std::optional<std::int64_t> ascending_rowid(std::size_t row) const override {
    return RoadGraph::id_at(first_ + row);
  }

  void column(std::size_t row, int column, sqlite3_context* out) const override {
    if (fed_digests_) {
      fed_digests_->column(first_ + row, column, out,
                           [&](DigestedRow<kColumns>& whole) { fill(row, whole); });
      return;
    }
    to_sqlite(row, column, out);
  }

  /// Row `row` as column() gives it to SQLite, the fid included. One thread per SegmentRows.
  void digest_row(std::size_t row, mapcheck::ColumnsDigester& digester) const override {
    fill(row, digested_);
    digested_.digest(digester);
  }

 private:
  /// Out of column()'s fed path, which SQLite calls for every value.
  [[gnu::noinline]] void to_sqlite(std::size_t row, int column, sqlite3_context* out) const {
    SqliteValue value{out};
    put(row, column, value);
  }

  /// Row `row` whole, the fid included, into `out`.
  void fill(std::size_t row, DigestedRow<kColumns>& out) const {
    out.integer(RoadGraph::id_at(first_ + row));
    for (int column = 1; column < kColumns; ++column) put(row, column, out);
  }

  /// Value `column` (1 .. kColumns - 1) of row `row`, put into `out` (SqliteValue or
  /// DigestedRow): the one place that says what the file holds.
  template <typename Out>
  void put(std::size_t row, int column, Out& out) const {
    const std::size_t index = first_ + row;
    const Segment& s = graph_.segments[index];
    if (column == 1) {
      schema::encode_linestring(graph_.line(s), srs_id_, line_bytes_);
      return out.lasting_blob(line_bytes_);
    }
    using C = schema::SegmentColumn;
    switch (static_cast<C>(column - 2)) {
      case C::osm_way_id:
        return out.integer(graph_.osm_way_id(s));
      case C::highway:
        return out.lasting_text(graph_.highway(s));
      case C::name: {
        const InternedText name = graph_.name(s);
        return name.empty() ? out.null() : out.lasting_text(name);
      }
      case C::length_m:
        return out.real(graph_.length_m(s));
      case C::from_node_id:
        return out.integer(graph_.from_node_id(s));
      case C::to_node_id:
        return out.integer(graph_.to_node_id(s));
      case C::oneway:
        return result(out, s.oneway);
      case C::tunnel:
        return result(out, s.tunnel);
      case C::bridge:
        return result(out, s.bridge);
      case C::class_cost:
        return result(out, graph_.class_cost(s));
      case C::junction_distance_m:
        return result(out, s.junction_distance_m);
      case C::radius_m:
        return result(out, s.radius_m);
      case C::curvature_level:
        return result(out, s.curvature_level);
      case C::curvature_cost:
        return result(out, s.curvature_cost);
      case C::elevation_m:
        return result(out, s.elevation_m);
      case C::slope_deg:
        return result(out, s.slope_deg);
      case C::grade_percent:
        return result(out, s.grade_percent);
      case C::tpi_small_m:
        return result(out, s.tpi_small_m);
      case C::tpi_large_m:
        return result(out, s.tpi_large_m);
      case C::landform:
        return s.landform.text() ? out.lasting_text(s.landform.text()) : out.null();
      case C::elevation_cost:
        return result(out, s.elevation_cost);
      case C::maxspeed_kmh:
        return result(out, graph_.maxspeed_kmh(s));
      case C::lanes:
        return result(out, graph_.lanes(s));
      case C::width_m:
        return result(out, graph_.width_m(s));
      case C::context_score:
        return result(out, s.context_score);
      case C::crossing_distance_m:
        return result(out, s.crossing_distance_m);
      case C::context_defaulted:
        return lasting_text(out, graph_.context_defaulted(s));
      case C::override_note:
        return lasting_text(out, graph_.override_note(s));
      case C::override_no_crossing:
        return result(out, s.override_no_crossing);
      case C::override_force_suitable:
        return result(out, s.override_force_suitable);
      case C::rank:
        return result(out, s.rank);
      case C::score:
        return result(out, s.score());
      case C::reasons: {
        return out.lasting_text(reasons_text(s.reasons));
      }
      case C::sight_forward_m:
        return result(out, s.sight_forward_m);
      case C::sight_backward_m:
        return result(out, s.sight_backward_m);
      case C::sight_min_m:
        return result(out, s.sight_min_m);
      case C::required_sight_m:
        return result(out, s.required_sight_m);
      case C::kerb: {
        const KerbFacts* kerb = kerb_at(index);
        return kerb && !kerb->kerb.empty() ? out.lasting_text(kerb->kerb) : out.null();
      }
      case C::kerb_height_m: {
        const KerbFacts* kerb = kerb_at(index);
        return kerb && kerb->kerb_height_m ? out.real(*kerb->kerb_height_m) : out.null();
      }
      case C::crossing_island: {
        const KerbFacts* kerb = kerb_at(index);
        return kerb ? optional_flag(out, kerb->island) : out.null();
      }
      case C::sidewalk_left:
        return optional_flag(out, graph_.pieces[s.piece_index].sidewalks.left);
      case C::sidewalk_right:
        return optional_flag(out, graph_.pieces[s.piece_index].sidewalks.right);
      case C::suitable:
        return result(out, suitable_on_centreline(index, s));
    }
    throw std::logic_error("segments writer: no column " + std::to_string(column));
  }

  /// The runtime's verdict on the segment's centreline under the map's defaults: the one judge
  /// (schema::judge_segment) and the kerb the map's robot profile cannot climb, as
  /// Map::assess_segment gives it (on the centreline the robot's side, and so the far-side
  /// pavement rule, is unknown).
  bool suitable_on_centreline(std::size_t index, const Segment& s) const {
    const auto score = s.score();
    const std::string& reasons = reasons_text(s.reasons);
    const schema::Verdict verdict = schema::judge_segment(
        {score ? std::optional<int>(*score) : std::nullopt,
         s.context_score ? std::optional<int>(*s.context_score) : std::nullopt, reasons, s.tunnel,
         s.override_no_crossing, s.override_force_suitable},
        {rule_.threshold, rule_.limited_visibility_unsuitable});
    const KerbFacts* kerb = kerb_at(index);
    const bool kerb_too_high =
        kerb && kerb->kerb_height_m && *kerb->kerb_height_m > rule_.max_kerb_height_m + 1e-9;
    return verdict.suitable && !kerb_too_high;
  }

  /// `reasons` joined with commas, as stored: each set joined once (a map has a few dozen) and
  /// kept while this source lives, so a row's text needs neither a join nor a copy.
  const std::string& reasons_text(const ReasonSet& reasons) const {
    const auto [it, added] = reasons_texts_.try_emplace(reasons.bits());
    if (added) it->second = reasons.joined(',');
    return it->second;
  }

  /// The segment's kerb facts (graph.kerbs holds the few segments that have any), or null.
  const KerbFacts* kerb_at(std::size_t index) const {
    const auto it = graph_.kerbs.find(index);
    return it == graph_.kerbs.end() ? nullptr : &it->second;
  }

  const RoadGraph& graph_;
  SuitabilityRule rule_;
  std::size_t first_, count_;
  std::int32_t srs_id_;
  FedRowDigests<kColumns>* fed_digests_;
  /// digest_row's row, its buffers reused.
  mutable DigestedRow<kColumns> digested_;
  /// The current row's geometry, encoded into the same buffer row after row (lasting_blob: it
  /// stays until the next row is filled, after SQLite has stored this one).
  mutable std::vector<std::uint8_t> line_bytes_;
  mutable std::unordered_map<std::uint16_t, std::string> reasons_texts_;  ///< reasons_text's
};

/// The segments table's digests computed from its rows as SegmentRows gives them to SQLite, in
/// fid order. `stop`: checked every 4096 rows, to end early (the result is then not used).
mapcheck::WrittenTableDigest digest_segment_rows(const RoadGraph& graph,
                                                 const SuitabilityRule& rule,
                                                 mapcheck::ColumnsDigester digester,
                                                 const std::atomic<bool>& stop) {
  const SegmentRows rows(graph, rule, 0, graph.segments.size());
  for (std::size_t row = 0; row < rows.row_count(); ++row) {
    if (row % 4096 == 0 && stop) throw std::runtime_error("segment digests stopped");
    rows.digest_row(row, digester);
  }
  return digester.finish();
}

std::string segment_column_list() {
  std::string names = "fid, geom";
  for (const schema::Column& column : schema::segment_columns()) {
    names += ", " + std::string(column.name);
  }
  return names;
}

/// Inserts every segment row, on both cores: the last rows go into a side database
/// (`<path>-rows`, same table) on a second thread while the first ones go into `db` and are
/// committed; then SQLite copies the side table's records into `db` without decoding them (its
/// "xfer" optimisation of INSERT INTO t SELECT * FROM t2, cheaper than encoding the rows again).
/// The rows and their order are the same as one insert of all rows. For a build without the
/// sight stage: with it, write_segment_rows_as_final() writes them while that stage runs.
void write_segment_rows(sqlite::Database& db, const std::string& db_path, const RoadGraph& graph,
                        const SuitabilityRule& rule, Progress& progress) {
  const std::size_t total = graph.segments.size();
  // The side thread takes more than half: this thread's rows cost more (their commit writes
  // them out after the insert; the side connection's small cache writes as it goes) and it
  // copies the side's rows after. docs/performance-log.md, "Build stages besides sight".
  constexpr std::size_t kFirstRowsPerMille = 360;
  const std::size_t split = total * kFirstRowsPerMille / 1000;
  const std::string side_path = db_path + kSideRowsSuffix;
  std::string create_table;
  {
    auto query = db.prepare("SELECT sql FROM sqlite_master WHERE type = 'table' AND name = ?");
    query.bind(1, schema::kSegmentsTable);
    if (!query.step()) throw std::logic_error("no segments table to write into");
    create_table = query.column_text(0);
  }
  std::atomic<std::size_t> side_rows_done{0};
  // Set when the first half fails (a full disk): the side thread then interrupts its own
  // statement at its next progress call (every 4096 rows), so that the error reaches the user at
  // once, not after the second half is encoded (seconds at country scale).
  std::atomic<bool> stop_side{false};
  std::future<void> side = std::async(std::launch::async, [&] {
    sqlite::Database side_db(side_path,
                             SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
                             mapcheck::bulk_io_vfs());
    side_db.exec("PRAGMA page_size = 4096");
    side_db.exec("PRAGMA journal_mode = OFF");
    side_db.exec("PRAGMA synchronous = OFF");
    side_db.exec("BEGIN");
    side_db.exec(create_table);
    insert_rows(side_db.handle(), schema::kSegmentsTable, segment_column_list(),
                SegmentRows(graph, rule, split, total), [&](std::size_t done) {
                  side_rows_done = done;
                  if (stop_side) sqlite3_interrupt(side_db.handle());
                });
    side_db.exec("COMMIT");
  });
  try {
    insert_rows(db.handle(), schema::kSegmentsTable, segment_column_list(),
                SegmentRows(graph, rule, 0, split),
                [&](std::size_t done) { progress.update(done + side_rows_done, total); });
    // Written out while the side thread still inserts. (ATTACH below cannot run inside a
    // transaction; with journal_mode OFF, COMMIT and BEGIN only end and start the batch.)
    db.exec("COMMIT");
  } catch (...) {
    stop_side = true;
    side.wait();  // it reads the graph and writes the side file: let it stop first
    std::remove(side_path.c_str());
    throw;
  }
  try {
    side.get();
  } catch (...) {
    std::remove(side_path.c_str());
    throw;
  }
  std::string table = "\"";  // (not "\"" + ...: GCC 12 warns falsely, -Wrestrict)
  table += schema::kSegmentsTable;
  table += '"';
  sqlite::Statement attach = db.prepare("ATTACH DATABASE ? AS side_rows");
  attach.bind(1, side_path);
  attach.run();
  db.exec("BEGIN");
  db.exec("INSERT INTO main." + table + " SELECT * FROM side_rows." + table);
  // All of them: the segments' digests are of every row (mapcheck::stamp_map_id does not count).
  if (sqlite3_changes64(db.handle()) != static_cast<sqlite3_int64>(total - split)) {
    throw std::logic_error("segments writer: not every row of the side database was copied");
  }
  db.exec("COMMIT");
  db.exec("DETACH DATABASE side_rows");
  std::remove(side_path.c_str());
  db.exec("BEGIN");
  progress.update(total, total);
}

/// Writes the open transaction's dirty pages to the file and frees the page cache's memory. The
/// same pages are written either way (now or at the commit), so the same bytes.
void write_out_pages(sqlite::Database& db) {
  // (sqlite3_db_cacheflush leaves the connection's message alone: it would say "not an error".)
  if (const int rc = sqlite3_db_cacheflush(db.handle()); rc != SQLITE_OK) {
    throw sqlite::sqlite_error(rc, sqlite3_errstr(rc));
  }
  sqlite3_db_release_memory(db.handle());
}

/// The extent of nothing: grow() with any box gives that box.
constexpr schema::Envelope kEmptyEnvelope{
    std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};

void grow(schema::Envelope& extent, const schema::Envelope& box) {
  extent.min_x = std::min(extent.min_x, box.min_x);
  extent.max_x = std::max(extent.max_x, box.max_x);
  extent.min_y = std::min(extent.min_y, box.min_y);
  extent.max_y = std::max(extent.max_y, box.max_y);
}

/// Fills the R*Tree with every segment's bounding box (bulk load: see rtree_bulk_load.hpp);
/// returns the extent of all segments.
schema::Envelope write_segment_rtree(sqlite::Database& db, const RoadGraph& graph) {
  schema::Envelope extent = kEmptyEnvelope;
  for (const Segment& s : graph.segments) grow(extent, schema::envelope_of(graph.line(s)));
  // The boxes are computed from the lines as the load needs them, not held: this runs beside
  // the cost stages, at the build's peak memory.
  bulk_load_rtree(
      db.handle(), std::string(schema::kSegmentsRtree), graph.segments.size(), [&](std::size_t i) {
        return RtreeEntry{RoadGraph::id_at(i), schema::envelope_of(graph.line(graph.segments[i]))};
      });
  return extent;
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
  schema::Envelope extent = kEmptyEnvelope;
  for (const RtreeEntry& e : entries) grow(extent, e.box);
  return extent;
}

/// The map's default verdict parameters, from the metadata the build records (the runtime reads
/// the same keys).
SuitabilityRule suitability_rule(const std::vector<std::pair<std::string, std::string>>& metadata) {
  SuitabilityRule rule;
  for (const auto& [key, value] : metadata) {
    if (key == schema::meta::kThresholdParam) rule.threshold = std::stod(value);
    if (key == schema::meta::kLimitedVisibilityUnsuitableParam) {
      rule.limited_visibility_unsuitable = std::stod(value) != 0.0;
    }
    if (key == schema::meta::kMaxKerbHeightParam) rule.max_kerb_height_m = std::stod(value);
  }
  return rule;
}

}  // namespace

GeoPackageWriter::GeoPackageWriter(const std::string& path, const geo::UtmZone& zone,
                                   const std::string& last_change)
    : zone_(zone), path_(path) {
  try {
    // Its pages go out 124 KiB a write call, not 4 KiB (mapcheck/bulk_io_vfs.hpp); the side
    // file attached to it later goes through the same VFS.
    db_ = std::make_unique<sqlite::Database>(
        path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX,
        mapcheck::bulk_io_vfs());
    // The file is private until renamed into place, so durability tricks are unnecessary:
    // no journal, no fsync; a fixed page size keeps the bytes identical across runs.
    db_->exec("PRAGMA page_size = 4096");
    db_->exec("PRAGMA journal_mode = OFF");
    db_->exec("PRAGMA synchronous = OFF");
    // A 64 MiB page cache: rows arrive in rowid order and the R*Tree is bulk-loaded, so a
    // larger cache only adds to the peak memory (256 MiB cost 190 MB more at 50x Monaco for
    // the same writing time).
    db_->exec("PRAGMA cache_size = -65536");
    db_->exec("BEGIN");
    for (const std::string& statement :
         schema::create_statements(zone.zone, zone.northern, last_change)) {
      db_->exec(statement);
    }
  } catch (const sqlite::sqlite_error& e) {
    throw OutputError(std::string("cannot write the database: ") + e.what());
  }
}

GeoPackageWriter::~GeoPackageWriter() {
  stop_digest_ = true;
}

mapcheck::WrittenTableDigest GeoPackageWriter::segment_digest() {
  if (!segment_digest_.valid()) {
    throw std::logic_error("GeoPackageWriter::segment_digest without finish, or twice");
  }
  return segment_digest_.get();
}

void GeoPackageWriter::write_segment_index(const RoadGraph& graph) {
  try {
    segment_extent_ = write_segment_rtree(*db_, graph);
    indexed_segments_ = graph.segments.size();
    // The index's pages (up to the 64 MiB cache, dirty in the open transaction) are written to
    // the file now and their memory freed: the cost stages after it (the terrain stage's tiles
    // and stored grid, the sight stage's obstacles) make the build's peak. The same pages are
    // written either way, so the same bytes.
    write_out_pages(*db_);
  } catch (const sqlite::sqlite_error& e) {
    throw OutputError(std::string("cannot write the database: ") + e.what());
  }
}

void GeoPackageWriter::write_segment_rows_as_final(
    const RoadGraph& graph, const std::vector<std::pair<std::string, std::string>>& metadata,
    DonePrefix& final_segments, const std::function<void(std::size_t, std::size_t)>& before_batch,
    std::size_t batch_rows) {
  const std::size_t total = graph.segments.size();
  if (!indexed_segments_ || *indexed_segments_ != total || final_segments.count() != total) {
    throw std::logic_error("write_segment_rows_as_final before write_segment_index of this graph");
  }
  const SuitabilityRule rule = suitability_rule(metadata);
  const std::string columns = segment_column_list();
  batch_rows = std::max<std::size_t>(batch_rows, 1);
  try {
    // The columns' declared types are the file's.
    mapcheck::ColumnsDigester digester(
        std::string(schema::kSegmentsTable),
        mapcheck::declared_columns(db_->handle(), schema::kSegmentsTable));
    FedRowDigests<SegmentRows::kColumns> fed_digests(digester);
    for (std::size_t begin = 0; begin < total;) {
      const std::size_t end =
          std::min(final_segments.wait_for(begin + batch_rows), begin + batch_rows);
      before_batch(begin, end);
      // The table's digests from the values as SQLite is given them, on this thread while the
      // producer runs.
      const SegmentRows rows(graph, rule, begin, end, &fed_digests);
      insert_rows(db_->handle(), schema::kSegmentsTable, columns, rows);
      // Every row inserted (insert_rows checks) was digested whole.
      if (digester.rows() != end) {
        throw std::logic_error("segments writer: " + std::to_string(digester.rows()) +
                               " rows digested of " + std::to_string(end));
      }
      // Written out beside the producer, not at the commit after it; and the cache stays one
      // batch's pages, beside the producer's peak memory.
      write_out_pages(*db_);
      streamed_rows_ = begin = end;
    }
    std::promise<mapcheck::WrittenTableDigest> digest;
    digest.set_value(digester.finish());
    segment_digest_ = digest.get_future();
  } catch (const sqlite::sqlite_error& e) {
    throw OutputError(std::string("cannot write the database: ") + e.what());
  }
}

void GeoPackageWriter::finish(const DatabaseContents& contents, Progress& progress,
                              std::future<void>* streamed_rows) {
  const RoadGraph& graph = *contents.graph;
  progress.start_stage("writing the GeoPackage", "segments");
  if (streamed_rows) {
    // What is left of the rows written beside the producer: the stage shows only that tail.
    // (Its thread may still be waiting for the index: nothing of the writer is read before.)
    while (streamed_rows->wait_for(std::chrono::milliseconds(100)) != std::future_status::ready) {
      progress.update(streamed_rows_, graph.segments.size());
    }
    streamed_rows->get();
  }
  if (!indexed_segments_ || *indexed_segments_ != graph.segments.size()) {
    throw std::logic_error("GeoPackageWriter::finish before write_segment_index of this graph");
  }
  try {
    write_rows_and_metadata(contents, progress, streamed_rows);
    // Only now: a statement still open would keep sqlite3_close from closing the file.
    db_.reset();
  } catch (const sqlite::sqlite_error& e) {
    throw OutputError(std::string("cannot write the database: ") + e.what());
  }
  progress.finish_stage(std::to_string(graph.segments.size()) + " segments, " +
                        std::to_string(contents.crossings ? contents.crossings->size() : 0) +
                        " crossings");
}

namespace {

/// The shortest text that reads back as the same double ("%.17g"): the stored extent is
/// exactly gpkg_contents', and the same inputs give the same text.
std::string exact(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

/// The coverage keys (schema::meta::kCoverage*) of a map whose segments span `extent`.
std::vector<std::pair<std::string_view, std::string>> coverage_metadata(
    const geo::UtmZone& zone, const schema::Envelope& extent) {
  const geo::LatLonBox box =
      geo::wgs84_box_of_utm_rectangle(zone, extent.min_x, extent.min_y, extent.max_x, extent.max_y);
  return {{schema::meta::kCoverageMinEasting, exact(extent.min_x)},
          {schema::meta::kCoverageMinNorthing, exact(extent.min_y)},
          {schema::meta::kCoverageMaxEasting, exact(extent.max_x)},
          {schema::meta::kCoverageMaxNorthing, exact(extent.max_y)},
          {schema::meta::kCoverageMinLat, exact(box.min_lat_deg)},
          {schema::meta::kCoverageMinLon, exact(box.min_lon_deg)},
          {schema::meta::kCoverageMaxLat, exact(box.max_lat_deg)},
          {schema::meta::kCoverageMaxLon, exact(box.max_lon_deg)}};
}

}  // namespace

void GeoPackageWriter::write_rows_and_metadata(const DatabaseContents& contents, Progress& progress,
                                               std::future<void>* streamed_rows) {
  const RoadGraph& graph = *contents.graph;
  sqlite::Database& db = *db_;
  if (!streamed_rows) {
    const SuitabilityRule rule = suitability_rule(contents.metadata);
    // The digests of the rows about to be written, from the same SegmentRows values, beside the
    // inserting threads and on through the writing after them (crossings, metadata, terrain),
    // until the map's identity needs them. The columns' declared types are the file's.
    mapcheck::ColumnsDigester digester(
        std::string(schema::kSegmentsTable),
        mapcheck::declared_columns(db.handle(), schema::kSegmentsTable));
    segment_digest_ = std::async(
        std::launch::async, [this, &graph, rule, digester = std::move(digester)]() mutable {
          return digest_segment_rows(graph, rule, std::move(digester), stop_digest_);
        });
    write_segment_rows(db, path_, graph, rule, progress);
  }
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
  set_extent(segment_extent_, schema::kSegmentsTable);
  if (contents.crossings) {
    const auto crossing_extent = write_crossings(db, *contents.crossings, zone_.epsg());
    if (crossing_extent) set_extent(*crossing_extent, schema::kCrossingsTable);
  }
  for (const std::string& statement : schema::rtree_trigger_statements()) db.exec(statement);

  auto insert_meta = db.prepare("INSERT INTO " + std::string(schema::kMetadataTable) +
                                " (key, value) VALUES (?, ?)");
  auto put = [&](std::string_view key, const std::string& value) {
    insert_meta.bind(1, key);
    insert_meta.bind(2, value);
    insert_meta.run();
  };
  put(schema::meta::kSchemaVersion, std::to_string(schema::kSchemaVersion));
  put(schema::meta::kUtmZone, std::to_string(zone_.zone));
  put(schema::meta::kUtmNorthern, zone_.northern ? "1" : "0");
  put(schema::meta::kEpsg, std::to_string(zone_.epsg()));
  put(schema::meta::kSegmentCount, std::to_string(graph.segments.size()));
  for (const auto& [key, value] : coverage_metadata(zone_, segment_extent_)) put(key, value);
  for (const auto& [key, value] : contents.metadata) put(key, value);
  for (const std::string& statement : qgis_style_statements(contents.last_change)) {
    db.exec(statement);
  }
  db.exec("COMMIT");
}

}  // namespace roadcross::preprocess
