// SHA-256 (FIPS 180-4) of a file, for the DB's record of its inputs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace roadcross::preprocess {

class Sha256 {
 public:
  Sha256();
  void update(const void* data, std::size_t size);
  /// Finishes and returns the digest as 64 lowercase hex digits.
  std::string hex_digest();

 private:
  void compress(const std::uint8_t* block);
  std::array<std::uint32_t, 8> state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// SHA-256 of a whole file; throws InputError naming the file if it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace roadcross::preprocess
