// The .pbf blobs' inflation (preprocess/src/osm/pbf_inflate.cpp: libdeflate, zlib for whatever it
// does not finish) on arbitrary streams: the same code, length and bytes as zlib's own
// uncompress() (__real_uncompress under the linker's --wrap). Input: a 2-byte little-endian room
// (the blob's declared size), then the zlib stream.
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

extern "C" int __real_uncompress(Bytef* dest, uLongf* dest_len, const Bytef* source,
                                 uLong source_len);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const std::size_t room = data[0] | (std::size_t{data[1]} << 8);
  const Bytef* stream = data + 2;
  const uLong stream_size = size - 2;
  std::vector<Bytef> wrapped(room + 1), zlib(room + 1);
  uLongf wrapped_length = room, zlib_length = room;
  const int wrapped_code = uncompress(wrapped.data(), &wrapped_length, stream, stream_size);
  const int zlib_code = __real_uncompress(zlib.data(), &zlib_length, stream, stream_size);
  if (wrapped_code != zlib_code) std::abort();
  if (wrapped_code == Z_OK && (wrapped_length != zlib_length ||
                               std::memcmp(wrapped.data(), zlib.data(), wrapped_length) != 0)) {
    std::abort();
  }
  return 0;
}
