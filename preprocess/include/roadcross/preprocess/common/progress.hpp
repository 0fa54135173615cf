// Progress reporting on a terminal: one line per stage, updated in place with percentage, rate
// and time left. Silent when stderr is not a terminal or when quiet, so logs and CI output stay
// clean. Every finished stage is also recorded (name, seconds, summary) for the final summary.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace roadcross::preprocess {

struct StageRecord {
  std::string name;
  double seconds = 0.0;
  std::string summary;
  std::int64_t peak_rss_kib = 0;  ///< the process's peak resident memory when the stage ended
};

class Progress {
 public:
  /// `enabled`: draw progress at all (false for --quiet or when stderr is not a TTY).
  explicit Progress(bool enabled) : enabled_(enabled) {}
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  ~Progress();

  /// True when stderr is a terminal.
  static bool stderr_is_terminal() noexcept;

  /// Starts a stage; `unit` names what update() counts ("MB" for bytes, "segments", ...).
  void start_stage(const std::string& name, const std::string& unit = "");
  /// `done` of `total` units; total 0 = unknown. Cheap to call often: the line is redrawn at
  /// most every 100 ms. Bytes are shown as MB when the unit is "MB".
  void update(std::uint64_t done, std::uint64_t total);
  /// Ends the stage with a short summary, e.g. "4 812 segments".
  void finish_stage(const std::string& summary);
  bool enabled() const noexcept { return enabled_; }
  /// The stages finished so far, in order.
  const std::vector<StageRecord>& stages() const noexcept { return stages_; }

 private:
  void draw(const std::string& line);
  bool enabled_;
  bool open_line_ = false;
  std::string stage_;
  std::string unit_;
  std::vector<StageRecord> stages_;
  std::chrono::steady_clock::time_point stage_start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace roadcross::preprocess
