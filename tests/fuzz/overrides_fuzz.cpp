// The operator overrides (GeoJSON) on arbitrary text: overrides within the documented bounds, or
// an InputError naming the file (and the feature), nothing else (no stray JSON exception).
#include <cstdlib>

#include "fuzz_support.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/context/overrides.hpp"

namespace rp = roadcross::preprocess;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(roadcross::fuzz::as_text(data, size));
  try {
    for (const rp::Override& o : rp::parse_overrides(text, "fuzz.geojson")) {
      if (o.context_delta < -rp::kMaxContextDelta || o.context_delta > rp::kMaxContextDelta ||
          o.note.size() > rp::kMaxOverrideNoteBytes || o.source != "fuzz.geojson" ||
          (o.polygons.empty() && o.osm_way_ids.empty())) {
        std::abort();
      }
      for (const std::int64_t id : o.osm_way_ids) {
        if (id <= 0) std::abort();
      }
    }
  } catch (const rp::InputError& e) {
    if (e.file() != "fuzz.geojson") std::abort();
  }
  return 0;
}
