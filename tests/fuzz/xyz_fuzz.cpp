// The XYZ elevation reader on arbitrary bytes: points or an InputError naming the file and the
// line, nothing else (no crash, no other exception, no altitude outside the documented range).
#include <cmath>
#include <cstdio>

#include "fuzz_support.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/terrain/elevation_input.hpp"

namespace rp = roadcross::preprocess;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const roadcross::fuzz::MemoryFile file(roadcross::fuzz::as_text(data, size));
  try {
    for (const rp::ElevationPoint& p : rp::read_xyz(file.path())) {
      if (!(p.z >= rp::kMinAltitudeM && p.z <= rp::kMaxAltitudeM) || !std::isfinite(p.x) ||
          !std::isfinite(p.y)) {
        std::fprintf(stderr, "read_xyz returned a point it should have refused\n");
        std::abort();
      }
    }
  } catch (const rp::InputError& e) {
    if (e.file() != file.path()) std::abort();  // the error must name the file
  }
  return 0;
}
