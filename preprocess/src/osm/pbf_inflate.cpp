#include "roadcross/preprocess/osm/pbf_inflate.hpp"

#include <libdeflate.h>
#include <zlib.h>

#include <atomic>
#include <memory>

namespace roadcross::preprocess {
namespace {

std::atomic<std::uint64_t> inflated_by_libdeflate{0};

/// One decompressor a thread (libosmium's decoding threads live as long as the process); null
/// when it could not be allocated, and then zlib does the work.
libdeflate_decompressor* thread_decompressor() {
  thread_local const std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)>
      decompressor(libdeflate_alloc_decompressor(), &libdeflate_free_decompressor);
  return decompressor.get();
}

}  // namespace

std::uint64_t blobs_inflated_by_libdeflate() {
  return inflated_by_libdeflate.load(std::memory_order_relaxed);
}

}  // namespace roadcross::preprocess

// The linker's names for zlib's own uncompress() and for its replacement (--wrap=uncompress).
extern "C" int __real_uncompress(Bytef* dest, uLongf* dest_len, const Bytef* source,
                                 uLong source_len);
extern "C" int __wrap_uncompress(Bytef* dest, uLongf* dest_len, const Bytef* source,
                                 uLong source_len);

/// zlib's uncompress() with the same results. libdeflate answers only when the zlib stream
/// inflates to exactly *dest_len bytes (a .pbf blob's declared raw size), its checksum
/// verified: zlib's own answer then is Z_OK with the same bytes and the same *dest_len. Anything
/// else — a corrupt, truncated or shorter stream, a buffer too small, a preset dictionary — is
/// handed to zlib from the start, so errors (and libosmium's messages naming them) are zlib's.
extern "C" int __wrap_uncompress(Bytef* dest, uLongf* dest_len, const Bytef* source,
                                 uLong source_len) {
  libdeflate_decompressor* decompressor = roadcross::preprocess::thread_decompressor();
  if (decompressor && libdeflate_zlib_decompress(decompressor, source, source_len, dest, *dest_len,
                                                 nullptr) == LIBDEFLATE_SUCCESS) {
    roadcross::preprocess::inflated_by_libdeflate.fetch_add(1, std::memory_order_relaxed);
    return Z_OK;
  }
  return __real_uncompress(dest, dest_len, source, source_len);
}
