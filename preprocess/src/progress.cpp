#include "roadcross/preprocess/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace roadcross::preprocess {

bool Progress::stderr_is_terminal() noexcept {
  return ::isatty(STDERR_FILENO) == 1;
}

Progress::~Progress() {
  if (open_line_) std::fputc('\n', stderr);
}

void Progress::start_stage(const std::string& name) {
  stage_ = name;
  stage_start_ = std::chrono::steady_clock::now();
  last_draw_ = {};
  draw(stage_ + " ...");
}

void Progress::update(std::uint64_t done, std::uint64_t total) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  char text[128];
  if (total > 0) {
    std::snprintf(text, sizeof text, " %5.1f %%",
                  100.0 * static_cast<double>(done) / static_cast<double>(total));
  } else {
    std::snprintf(text, sizeof text, " %llu", static_cast<unsigned long long>(done));
  }
  draw(stage_ + text);
}

void Progress::finish_stage(const std::string& summary) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start_).count();
  char text[64];
  std::snprintf(text, sizeof text, " (%.2f s)", seconds);
  draw(stage_ + ": " + summary + text);
  if (enabled_) {
    std::fputc('\n', stderr);
    open_line_ = false;
  }
}

void Progress::draw(const std::string& line) {
  if (!enabled_) return;
  std::fprintf(stderr, "\r\033[K%s", line.c_str());
  std::fflush(stderr);
  open_line_ = true;
}

}  // namespace roadcross::preprocess
