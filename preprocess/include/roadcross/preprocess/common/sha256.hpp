// SHA-256 (FIPS 180-4) of a file, for the DB's record of its inputs.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace roadcross::preprocess {

/// SHA-256's chaining state (a..h).
using Sha256State = std::array<std::uint32_t, 8>;

/// Runs SHA-256's compression over `blocks` 64-byte blocks at `data` (any alignment).
using Sha256Compress = void (*)(Sha256State& state, const std::uint8_t* data, std::size_t blocks);

/// The portable compression (FIPS 180-4 as written).
void sha256_compress_portable(Sha256State& state, const std::uint8_t* data, std::size_t blocks);

/// The compression on the x86 SHA extensions (SHA-NI: ~5x the portable one's rate), or null
/// where the CPU or the build has none. The same digests (tested against the portable one).
Sha256Compress sha256_compress_hardware();

class Sha256 {
 public:
  /// `compress`: the compression to use; null: the hardware one where there is one.
  explicit Sha256(Sha256Compress compress = nullptr);
  void update(const void* data, std::size_t size);
  /// Finishes and returns the digest as 64 lowercase hex digits.
  std::string hex_digest();

 private:
  Sha256Compress compress_;
  Sha256State state_;
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
};

/// SHA-256 of a whole file; throws InputError naming the file if it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace roadcross::preprocess
