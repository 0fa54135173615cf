// One pass over an OSM file with libosmium, shared by every reader of the build (the road
// network and, through it, the sight stage's obstacles).
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <osmium/io/any_input.hpp>
#include <osmium/thread/pool.hpp>
#include <osmium/visitor.hpp>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "roadcross/preprocess/common/progress.hpp"

namespace roadcross::preprocess {

/// The threads that decode .pbf blocks for every OSM reader of the build: OSMIUM_POOL_THREADS
/// when set, else libosmium's default (the cores less two) but at least two. With one, a 2-core
/// machine's second core idles through much of each pass: the ways pass decodes every node
/// block before its first way reaches the handlers.
inline osmium::thread::Pool& osm_decoder_pool() {
  static osmium::thread::Pool pool{
      osmium::config::get_pool_threads() != 0
          ? osmium::thread::Pool::default_num_threads
          : std::max(2, static_cast<int>(std::thread::hardware_concurrency()) - 2)};
  return pool;
}

/// Reads the `entities` of the file at `path` and hands every object to each of `handlers` in
/// file order, reporting the bytes read. libosmium decodes .pbf blocks on its worker threads
/// (osm_decoder_pool) while the handlers run on this one.
template <typename... Handlers>
void read_osm_pass(const std::string& path, osmium::osm_entity_bits::type entities,
                   Progress& progress, Handlers&... handlers) {
  osmium::io::Reader reader{osmium::io::File{path}, entities, osm_decoder_pool()};
  const std::uint64_t size = reader.file_size();
  while (osmium::memory::Buffer buffer = reader.read()) {
    osmium::apply(buffer, handlers...);
    progress.update(reader.offset(), size);
  }
  reader.close();
}

/// Several OSM files read as one stream, as `osmium merge` would write them: objects in
/// (type, id) order, and an object that several files hold (same type and id) handed on once,
/// in its newest version (the highest version number; on a tie, the first file's). Each file
/// must be sorted by type and id, as OSM extracts are; one that is not throws InputError
/// naming it and the object out of order.
class MergedOsmReader {
 public:
  MergedOsmReader(const std::vector<std::string>& paths, osmium::osm_entity_bits::type entities);
  ~MergedOsmReader();
  MergedOsmReader(const MergedOsmReader&) = delete;
  MergedOsmReader& operator=(const MergedOsmReader&) = delete;

  /// The next object of the merged stream, or nullptr at the end of all files. Valid until the
  /// next call.
  osmium::OSMObject* next();
  /// Bytes read so far and in all, over all files (for the progress display).
  std::uint64_t offset() const;
  std::uint64_t size() const noexcept { return size_; }

 private:
  class Input;
  /// (type, id > 0, |id|): osmium's order of objects, without version and timestamp.
  using ObjectKey = std::tuple<osmium::item_type, bool, osmium::unsigned_object_id_type>;
  std::vector<std::unique_ptr<Input>> inputs_;
  std::uint64_t size_ = 0;
  std::optional<ObjectKey> last_;  ///< the object handed on last
};

/// read_osm_pass over several files merged into one stream (MergedOsmReader); one file is read
/// as read_osm_pass reads it.
template <typename... Handlers>
void read_osm_pass(const std::vector<std::string>& paths, osmium::osm_entity_bits::type entities,
                   Progress& progress, Handlers&... handlers) {
  if (paths.size() == 1) return read_osm_pass(paths.front(), entities, progress, handlers...);
  MergedOsmReader reader(paths, entities);
  std::uint64_t objects = 0;
  while (osmium::OSMObject* object = reader.next()) {
    osmium::apply_item(*object, handlers...);
    // The progress display wants a few updates a second, not one per object.
    if (++objects % 65536 == 0) progress.update(reader.offset(), reader.size());
  }
  progress.update(reader.offset(), reader.size());
}

}  // namespace roadcross::preprocess
