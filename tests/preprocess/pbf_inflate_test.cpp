// The .pbf blobs' inflation (preprocess/src/osm/pbf_inflate.cpp): libosmium's uncompress() calls
// reach libdeflate through the linker's --wrap, and every answer is zlib's own. zlib itself
// (__real_uncompress, the same function under the linker's other name) is the reference: for
// streams compressed by zlib, truncated, cut short or damaged byte by byte, the replacement
// must return zlib's code, and on success zlib's bytes and length.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdint>
#include <osmium/handler.hpp>
#include <osmium/io/pbf_input.hpp>
#include <osmium/visitor.hpp>
#include <random>
#include <string>
#include <vector>

#include "roadcross/preprocess/osm/pbf_inflate.hpp"

extern "C" int __real_uncompress(Bytef* dest, uLongf* dest_len, const Bytef* source,
                                 uLong source_len);

namespace rp = roadcross::preprocess;

namespace {

using Bytes = std::vector<unsigned char>;

Bytes compressed(const Bytes& raw, int level) {
  uLongf size = compressBound(raw.size());
  Bytes out(size);
  EXPECT_EQ(compress2(out.data(), &size, raw.data(), raw.size(), level), Z_OK);
  out.resize(size);
  return out;
}

/// One call's outcome: the code, the length reported and the bytes written (on success).
struct Outcome {
  int code = 0;
  uLongf length = 0;
  Bytes bytes;
  bool operator==(const Outcome&) const = default;
};

/// `inflate` on `stream` into a buffer of `room` bytes; the bytes are kept only on Z_OK (else
/// zlib leaves them unspecified).
template <typename Inflate>
Outcome run(Inflate inflate, const Bytes& stream, std::size_t room) {
  Outcome out;
  Bytes buffer(room + 1, 0);  // + 1: a valid pointer for room 0
  out.length = room;
  out.code = inflate(buffer.data(), &out.length, stream.data(), stream.size());
  if (out.code == Z_OK) out.bytes.assign(buffer.begin(), buffer.begin() + out.length);
  return out;
}

Outcome by_wrapper(const Bytes& stream, std::size_t room) {
  return run(::uncompress, stream, room);
}
Outcome by_zlib(const Bytes& stream, std::size_t room) {
  return run(__real_uncompress, stream, room);
}

/// Text-like bytes (compressible, as a .pbf block's strings and varints are) and noise.
Bytes sample(std::size_t size, bool noise, unsigned seed) {
  std::mt19937 random(seed);
  Bytes out(size);
  for (std::size_t i = 0; i < size; ++i) {
    out[i] =
        noise ? static_cast<unsigned char>(random())
              : static_cast<unsigned char>("highway=residential;name=Rue "[i % 29] + (i / 997) % 3);
  }
  return out;
}

TEST(PbfInflate, WholeStreamsInflateToTheirBytesAsZlibDoes) {
  const std::uint64_t before = rp::blobs_inflated_by_libdeflate();
  int streams = 0;
  for (const std::size_t size :
       {std::size_t{1}, std::size_t{100}, std::size_t{65536}, std::size_t{1} << 20}) {
    for (const bool noise : {false, true}) {
      for (const int level : {0, 1, 6, 9}) {
        const Bytes raw = sample(size, noise, static_cast<unsigned>(size + level));
        const Bytes stream = compressed(raw, level);
        const Outcome wrapped = by_wrapper(stream, raw.size());
        EXPECT_EQ(wrapped.code, Z_OK);
        EXPECT_EQ(wrapped.length, raw.size());
        EXPECT_TRUE(wrapped.bytes == raw) << size << " bytes, level " << level;
        EXPECT_EQ(wrapped, by_zlib(stream, raw.size()));
        ++streams;
      }
    }
  }
  // Each of them inflated by libdeflate, not handed to zlib.
  EXPECT_EQ(rp::blobs_inflated_by_libdeflate() - before, std::uint64_t(streams));
}

TEST(PbfInflate, RoomTooSmallOrTooLargeGivesZlibsAnswer) {
  const Bytes raw = sample(5000, false, 7);
  const Bytes stream = compressed(raw, 6);
  for (const std::size_t room :
       {std::size_t{0}, std::size_t{1}, std::size_t{4999}, std::size_t{5001}, std::size_t{10000}}) {
    const Outcome wrapped = by_wrapper(stream, room);
    EXPECT_EQ(wrapped, by_zlib(stream, room)) << "room " << room;
  }
  EXPECT_EQ(by_wrapper(stream, 4999).code, Z_BUF_ERROR);  // zlib's "buffer error"
  EXPECT_EQ(by_wrapper(stream, 10000).length, 5000u);     // shorter: zlib's Z_OK and length
  // An empty stream inflated into no room at all.
  EXPECT_EQ(by_wrapper(compressed({}, 6), 0), by_zlib(compressed({}, 6), 0));
}

TEST(PbfInflate, TruncatedAndTrailedStreamsGiveZlibsAnswer) {
  const Bytes raw = sample(20000, false, 3);
  const Bytes stream = compressed(raw, 9);
  for (std::size_t cut = 0; cut < stream.size(); cut += cut < 16 ? 1 : 97) {
    const Bytes head(stream.begin(), stream.begin() + static_cast<std::ptrdiff_t>(cut));
    EXPECT_EQ(by_wrapper(head, raw.size()), by_zlib(head, raw.size())) << "cut at " << cut;
  }
  // The last bytes are the Adler-32 checksum: without them the output is whole but unchecked.
  const Bytes no_checksum(stream.begin(), stream.end() - 4);
  EXPECT_NE(by_wrapper(no_checksum, raw.size()).code, Z_OK);
  Bytes trailed = stream;  // bytes after the stream's end are not read
  trailed.insert(trailed.end(), {1, 2, 3, 4, 5});
  EXPECT_EQ(by_wrapper(trailed, raw.size()).code, Z_OK);
  EXPECT_EQ(by_wrapper(trailed, raw.size()), by_zlib(trailed, raw.size()));
}

TEST(PbfInflate, DamagedStreamsGiveZlibsAnswer) {
  const Bytes raw = sample(3000, false, 11);
  const Bytes stream = compressed(raw, 6);
  int failed = 0;
  for (std::size_t at = 0; at < stream.size(); ++at) {
    for (const int flip : {0x01, 0x80, 0xFF}) {
      Bytes damaged = stream;
      damaged[at] = static_cast<unsigned char>(damaged[at] ^ flip);
      const Outcome wrapped = by_wrapper(damaged, raw.size());
      EXPECT_EQ(wrapped, by_zlib(damaged, raw.size())) << "byte " << at << " ^ " << int(flip);
      failed += wrapped.code != Z_OK ? 1 : 0;
    }
  }
  EXPECT_GT(failed, 0);
  // A preset dictionary (FDICT in the header, the check bits fixed): zlib's Z_DATA_ERROR.
  Bytes with_dictionary = stream;
  with_dictionary[1] = static_cast<unsigned char>((with_dictionary[1] | 0x20) & 0xE0);
  with_dictionary[1] = static_cast<unsigned char>(
      with_dictionary[1] + (31 - (with_dictionary[0] * 256 + with_dictionary[1]) % 31) % 31);
  EXPECT_EQ(by_wrapper(with_dictionary, raw.size()).code, Z_DATA_ERROR);
  EXPECT_EQ(by_wrapper(with_dictionary, raw.size()), by_zlib(with_dictionary, raw.size()));
}

struct Counts : osmium::handler::Handler {
  std::uint64_t nodes = 0, ways = 0, relations = 0;
  void node(const osmium::Node&) { ++nodes; }
  void way(const osmium::Way&) { ++ways; }
  void relation(const osmium::Relation&) { ++relations; }
};

// libosmium's reader goes through the replacement: Monaco's four zlib blobs (the header and
// three blocks) are inflated by libdeflate, and the objects are those `osmium fileinfo -e`
// counts in the file (180 118 nodes, 27 377 ways, 212 relations).
TEST(PbfInflate, LibosmiumReadsARealFileThroughIt) {
  const std::uint64_t before = rp::blobs_inflated_by_libdeflate();
  osmium::io::Reader reader{std::string(ROADCROSS_MAPS_DIR) + "/monaco/monaco.osm.pbf"};
  Counts counts;
  osmium::apply(reader, counts);
  reader.close();
  EXPECT_EQ(counts.nodes, 180118u);
  EXPECT_EQ(counts.ways, 27377u);
  EXPECT_EQ(counts.relations, 212u);
  EXPECT_EQ(rp::blobs_inflated_by_libdeflate() - before, 4u);
}

}  // namespace
