// SHA-256 of the build's input files (the DB records them; OpenSSL's libcrypto), in bytes per
// second. The build hashes the OSM file (and the DEMs) on a thread
// of its own beside the stages that use both cores, so its rate is core time taken from them.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "roadcross/preprocess/common/sha256.hpp"

namespace rp = roadcross::preprocess;

namespace {

void BM_Sha256(benchmark::State& state) {
  std::vector<std::uint8_t> data(std::size_t(1) << 20);  // 1 MiB, as the file is read in pieces
  for (std::size_t i = 0; i < data.size(); ++i)
    data[i] = static_cast<std::uint8_t>(i * 2654435761u);
  for (auto _ : state) {
    rp::Sha256 hash;
    hash.update(data.data(), data.size());
    benchmark::DoNotOptimize(hash.hex_digest());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * data.size()));
}
BENCHMARK(BM_Sha256);

}  // namespace

BENCHMARK_MAIN();
