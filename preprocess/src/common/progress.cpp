#include "roadcross/preprocess/common/progress.hpp"

#include "roadcross/preprocess/common/format.hpp"

#include <sys/resource.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace roadcross::preprocess {

std::string format_count(double value) {
  if (!std::isfinite(value)) return "-";
  char digits[400];  // %.0f of the largest double has 309 digits
  const int count = std::snprintf(digits, sizeof digits, "%.0f", std::fabs(value));
  // Built forwards: GCC 12 warns (-Wrestrict, a false positive) on string::insert at -O3.
  std::string text;
  if (value < 0 && !(count == 1 && digits[0] == '0')) text += '-';
  for (int i = 0; i < count; ++i) {
    if (i > 0 && (count - i) % 3 == 0) text += ',';
    text += digits[i];
  }
  return text;
}

std::string format_quantity(double value) {
  if (!std::isfinite(value)) return "-";
  if (std::fabs(value) >= 99.95) return format_count(value);
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

bool Progress::stderr_is_terminal() noexcept {
  return ::isatty(STDERR_FILENO) == 1;
}

Progress::~Progress() {
  if (open_line_) std::fputc('\n', stderr);
}

void Progress::start_stage(const std::string& name, const std::string& unit) {
  stage_ = name;
  unit_ = unit;
  stage_start_ = std::chrono::steady_clock::now();
  last_draw_ = {};
  draw(stage_ + " ...");
}

void Progress::update(std::uint64_t done, std::uint64_t total) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double elapsed_s = std::chrono::duration<double>(now - stage_start_).count();
  const double scale = unit_ == "MB" ? 1e-6 : 1.0;
  const double rate = elapsed_s > 0.0 ? static_cast<double>(done) * scale / elapsed_s : 0.0;
  char text[160];
  if (total > 0 && done > 0) {
    const double fraction = static_cast<double>(done) / static_cast<double>(total);
    const double eta_s = elapsed_s * (1.0 - fraction) / fraction;
    std::snprintf(text, sizeof text, " %5.1f %%  %s %s/s  %.0f s left", 100.0 * fraction,
                  format_quantity(rate).c_str(), unit_.c_str(), eta_s);
  } else {
    std::snprintf(text, sizeof text, " %s %s  %s %s/s",
                  format_quantity(static_cast<double>(done) * scale).c_str(), unit_.c_str(),
                  format_quantity(rate).c_str(), unit_.c_str());
  }
  draw(stage_ + text);
}

void Progress::finish_stage(const std::string& summary) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - stage_start_).count();
  struct rusage usage {};
  const std::int64_t peak_kib = ::getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_maxrss : 0;
  stages_.push_back({stage_, seconds, summary, peak_kib});
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
