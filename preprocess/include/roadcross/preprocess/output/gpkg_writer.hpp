// Writes the road graph's segments and the metadata into a roadcross GeoPackage, atomically:
// everything goes to a temporary file beside the target, renamed over it only on success.
#pragma once

#include <atomic>
#include <cstddef>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "roadcross/files/atomic_file.hpp"
#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/preprocess/common/done_prefix.hpp"
#include "roadcross/preprocess/context/crossings.hpp"
#include "roadcross/preprocess/graph/segments.hpp"

namespace roadcross::sqlite {
class Database;
}

namespace roadcross::preprocess {

class Progress;

struct DatabaseContents {
  const RoadGraph* graph = nullptr;
  /// Rows of the crossings table (may be null: an empty table).
  const std::vector<Crossing>* crossings = nullptr;
  /// Key/value pairs for roadcross_metadata (schema version, zone and segment count are added
  /// by the writer).
  std::vector<std::pair<std::string, std::string>> metadata;
  /// gpkg_contents.last_change, ISO 8601. An input (the newest OSM timestamp), not "now", so
  /// the output is byte-identical for identical inputs.
  std::string last_change = "1970-01-01T00:00:00.000Z";
};

/// The build's temporary output (files::AtomicFile, with SQLite's "-journal" and the writer's
/// "-rows" side file of a build without the sight stage), registered with the interrupt handlers;
/// removed unless committed.
class AtomicOutput {
 public:
  /// Creates `<target>.tmp-XXXXXX` beside `target`; throws OutputError naming the target if the
  /// folder is not writable or something other than a regular file is at the target.
  explicit AtomicOutput(const std::string& target);
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  ~AtomicOutput();

  const std::string& temp_path() const noexcept { return file_->temp_path(); }
  const std::string& target_path() const noexcept { return file_->target_path(); }
  /// files::AtomicFile::start_writeback of the temporary file.
  void start_writeback() const noexcept { file_->start_writeback(); }
  /// Flushes and renames the temporary file onto the target (atomic on POSIX file systems).
  void commit();

 private:
  std::unique_ptr<files::AtomicFile> file_;
};

/// Writes a roadcross GeoPackage in steps, so that the segments' spatial index (which needs
/// only their lines) can be written on another thread while the cost stages fill the terms:
///
///     GeoPackageWriter writer(path, graph.zone, last_change);  // creates the tables
///     auto index = std::async(std::launch::async, [&] { writer.write_segment_index(graph); });
///     ...  // cost stages: they must not change the segments' number, ids or lines
///     index.get();
///     writer.finish(contents, progress);  // segment rows, crossings, metadata; closes the file
///     mapcheck::stamp_map_id(path, threads, writer.segment_digest());
///
/// or, with the segment rows written on a thread of their own while the sight stage computes
/// the last fields (the rows become final in a growing prefix, DonePrefix):
///
///     index.get();
///     auto rows = std::async(std::launch::async, [&] {
///       writer.write_segment_rows_as_final(graph, metadata, done, before_batch, batch);
///     });
///     compute_sight(graph, ..., &done);
///     writer.finish(contents, progress, &rows);  // waits for the rows, then writes the rest
///
/// Methods throw OutputError (SQLite's message); the caller removes the file (AtomicOutput).
class GeoPackageWriter {
 public:
  /// Creates the schema in `path` (a new or empty file) in an open transaction.
  GeoPackageWriter(const std::string& path, const geo::UtmZone& zone,
                   const std::string& last_change);
  GeoPackageWriter(const GeoPackageWriter&) = delete;
  GeoPackageWriter& operator=(const GeoPackageWriter&) = delete;
  ~GeoPackageWriter();

  /// The segments' R*Tree and extent. Reads only the segments' ids and lines.
  void write_segment_index(const RoadGraph& graph);
  /// The segment rows, in fid order, inserted on the calling thread while another stage (the
  /// producer of `final_segments`) still fills their last fields: each batch of rows as soon as
  /// its segments are final, at least `batch_rows` rows a batch (fewer at the end). First
  /// `before_batch(begin, end)` fills what the rows [begin, end) need that the producer does not
  /// (their ranks). Each batch's pages are written out and their memory released after it, so
  /// the page cache does not add to the producer's memory. After write_segment_index(); `metadata`:
  /// the build's parameters (the stored verdict's). Throws OutputError (a full disk), or
  /// DonePrefix::Abandoned when the producer stops; stop `final_segments` on any exception.
  void write_segment_rows_as_final(
      const RoadGraph& graph, const std::vector<std::pair<std::string, std::string>>& metadata,
      DonePrefix& final_segments, const std::function<void(std::size_t, std::size_t)>& before_batch,
      std::size_t batch_rows);
  /// Everything else, after write_segment_index() of the same graph has returned; commits.
  /// `streamed_rows`: the future of a write_segment_rows_as_final() call, waited for (its
  /// progress shown, its exception rethrown) in place of writing the segment rows. Without it,
  /// finish() writes them and also starts computing the segments table's digests from the rows
  /// it writes, on a thread of its own, which reads the graph until segment_digest() returns
  /// (or the writer is destroyed); write_segment_rows_as_final() digests its rows itself.
  void finish(const DatabaseContents& contents, Progress& progress,
              std::future<void>* streamed_rows = nullptr);
  /// The segments table's column digests computed from the rows written (not read back from
  /// the file): waits for them. Once, after finish(). Throws what the digester threw.
  mapcheck::WrittenTableDigest segment_digest();

 private:
  void write_rows_and_metadata(const DatabaseContents& contents, Progress& progress,
                               std::future<void>* streamed_rows);

  geo::UtmZone zone_;
  std::string path_;
  std::unique_ptr<sqlite::Database> db_;
  schema::Envelope segment_extent_{};
  std::optional<std::size_t> indexed_segments_;
  /// Segment rows write_segment_rows_as_final() has inserted (read by finish()'s progress).
  std::atomic<std::size_t> streamed_rows_{0};
  /// Set by the destructor: the digest thread stops early. Declared before the future, whose
  /// destruction waits for the thread.
  std::atomic<bool> stop_digest_{false};
  std::future<mapcheck::WrittenTableDigest> segment_digest_;
};

}  // namespace roadcross::preprocess
