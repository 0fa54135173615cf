// One pass over an OSM file with libosmium, shared by every reader of the build (the road
// network and, through it, the sight stage's obstacles).
#pragma once

#include <cstdint>
#include <osmium/io/any_input.hpp>
#include <osmium/visitor.hpp>
#include <string>

#include "roadcross/preprocess/common/progress.hpp"

namespace roadcross::preprocess {

/// Reads the `entities` of the file at `path` and hands every object to each of `handlers` in
/// file order, reporting the bytes read. libosmium decodes .pbf blocks on its own worker
/// threads while the handlers run on this one.
template <typename... Handlers>
void read_osm_pass(const std::string& path, osmium::osm_entity_bits::type entities,
                   Progress& progress, Handlers&... handlers) {
  osmium::io::Reader reader{osmium::io::File{path}, entities};
  const std::uint64_t size = reader.file_size();
  while (osmium::memory::Buffer buffer = reader.read()) {
    osmium::apply(buffer, handlers...);
    progress.update(reader.offset(), size);
  }
  reader.close();
}

}  // namespace roadcross::preprocess
