// SHA-256 of the build's input files, for the DB's record of its inputs. OpenSSL's libcrypto
// does the hashing (it uses the CPU's SHA extensions where there are some); this header keeps
// OpenSSL out of its includers.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

namespace roadcross::preprocess {

class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;

  void update(const void* data, std::size_t size);
  /// Finishes and returns the digest as 64 lowercase hex digits.
  std::string hex_digest();

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

/// SHA-256 of a whole file; throws InputError naming the file if it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace roadcross::preprocess
