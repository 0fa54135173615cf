// `roadcross batch` request lines on arbitrary bytes, against a small real map: one answer line
// that is valid JSON for every input line, never a crash, a hang or an exception.
#include <cstdlib>
#include <memory>
#include <nlohmann/json.hpp>

#include "fuzz_support.hpp"
#include "request_lines.hpp"

namespace {

roadcross::Map& fuzz_map() {
  static std::unique_ptr<roadcross::Map> map = [] {
    auto opened = roadcross::Map::open(roadcross::fuzz::required_env("ROADCROSS_FUZZ_MAP"));
    if (!opened.ok()) {
      std::fprintf(stderr, "ROADCROSS_FUZZ_MAP: %s\n", opened.status.message.c_str());
      std::abort();
    }
    return std::make_unique<roadcross::Map>(std::move(*opened));
  }();
  return *map;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string line(roadcross::fuzz::as_text(data, size));
  bool failed = false;
  const std::string answer = roadcross::cli::batch_answer(fuzz_map(), line, 1, failed);
  // The answer is one line of JSON whatever the request (bad bytes are replaced, not fatal).
  if (answer.find('\n') != std::string::npos) std::abort();
  const nlohmann::json parsed = nlohmann::json::parse(answer, nullptr, false);
  if (parsed.is_discarded() || parsed.value("line", 0) != 1) std::abort();
  return 0;
}
