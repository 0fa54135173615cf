// SHA-256 against the FIPS 180-4 examples and against sha256sum (the value in maps/README.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "osm_fixture.hpp"
#include "roadcross/preprocess/common/errors.hpp"
#include "roadcross/preprocess/common/sha256.hpp"

namespace rp = roadcross::preprocess;

namespace {

std::string sha256_of(const std::string& text) {
  rp::Sha256 hash;
  hash.update(text.data(), text.size());
  return hash.hex_digest();
}

TEST(Sha256, FipsExamples) {
  EXPECT_EQ(sha256_of(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_of("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_of("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  rp::Sha256 million;
  const std::string chunk(1000, 'a');
  for (int i = 0; i < 1000; ++i) million.update(chunk.data(), chunk.size());
  EXPECT_EQ(million.hex_digest(),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, BoundaryLengths) {
  // 55, 56 and 64 bytes straddle the padding block boundary; values from `sha256sum`.
  EXPECT_EQ(sha256_of(std::string(55, 'a')),
            "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  EXPECT_EQ(sha256_of(std::string(56, 'a')),
            "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  EXPECT_EQ(sha256_of(std::string(64, 'a')),
            "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST(Sha256, PiecesGiveTheDigestOfTheWhole) {
  // The million 'a's of the FIPS example fed in pieces of 0..199 bytes.
  std::mt19937 random(20261202);
  const std::string data(1000000, 'a');
  rp::Sha256 hash;
  for (std::size_t at = 0; at < data.size();) {
    const std::size_t piece = std::min<std::size_t>(random() % 200, data.size() - at);
    hash.update(data.data() + at, piece);
    at += piece;
  }
  EXPECT_EQ(hash.hex_digest(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, FileMatchesProvenance) {
  EXPECT_EQ(rp::sha256_of_file(std::string(ROADCROSS_MAPS_DIR) +
                               "/prague/prague_nove_mesto_roads_2017.osm"),
            "f935f5a11158dbe9206b90518044d44bcc6f491e57fd4a7e52155b239adea5d3");
}

TEST(Sha256, MissingFileNamesIt) {
  try {
    rp::sha256_of_file("/nonexistent/roadcross.osm");
    FAIL() << "expected InputError";
  } catch (const rp::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/roadcross.osm"), std::string::npos);
  }
}

}  // namespace
