// The inflation of .pbf blobs: libosmium calls zlib's uncompress() for each one, and the
// executables that link roadcross::preprocess have that call redirected (the linker's
// --wrap=uncompress, preprocess/CMakeLists.txt) to one that inflates with libdeflate, about
// twice as fast as zlib 1.2, and leaves every case it does not finish to zlib itself, so that
// libosmium sees zlib's results and errors (docs/architecture.md, "Reading OSM").
#pragma once

#include <cstdint>

namespace roadcross::preprocess {

/// How many blobs libdeflate has inflated in this process (those left to zlib are not counted):
/// for the tests, which check that the redirection is in place.
std::uint64_t blobs_inflated_by_libdeflate();

}  // namespace roadcross::preprocess
