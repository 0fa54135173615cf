// Writes the road graph's segments and the metadata into a roadcross GeoPackage, atomically:
// everything goes to a temporary file beside the target, renamed over it only on success.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "roadcross/preprocess/crossings.hpp"
#include "roadcross/preprocess/segments.hpp"

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

/// A temporary output file that is removed unless committed.
class AtomicOutput {
 public:
  /// Creates `<target>.tmp-XXXXXX` beside `target`; throws OutputError if the directory is not
  /// writable.
  explicit AtomicOutput(std::string target);
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  ~AtomicOutput();

  const std::string& temp_path() const noexcept { return temp_path_; }
  const std::string& target_path() const noexcept { return target_; }
  /// Renames the temporary file onto the target (atomic on POSIX file systems).
  void commit();

 private:
  std::string target_;
  std::string temp_path_;
  bool committed_ = false;
};

/// Writes a complete GeoPackage at `path` (which must not exist or be empty).
void write_geopackage(const std::string& path, const DatabaseContents& contents,
                      Progress& progress);

}  // namespace roadcross::preprocess
