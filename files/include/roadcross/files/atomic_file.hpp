// Output files that are never half-written and never replace what is not a regular file.
//
// Every output (the build's GeoPackage, render's PNG, export's GeoJSON, view's files) is
// written to `<target>.tmp-XXXXXX` in the target's folder and renamed onto the target only
// when complete and flushed to disk, so the old file stays whole after any failure (full disk,
// interrupt, crash). The target must be absent or a regular file: a device node, FIFO, socket,
// folder or symbolic link at the target is an error, not something to rename over.
//
// A living writer holds an exclusive flock(2) on its temporary file; the kernel drops it when
// the process ends, however it ends (SIGKILL included). remove_dead_temporaries() uses that to
// tell what a killed writer left (no lock held) from a running writer's file (lock held).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace roadcross::files {

/// Throws std::runtime_error naming `path` unless it can be an output file: not empty, its
/// folder exists and is writable, and nothing or a regular file is at `path`.
void check_output_path(const std::string& path);

/// A temporary file beside the target, removed unless committed.
class AtomicFile {
 public:
  /// Called with the temporary name before the file is created, and with nullptr once it is
  /// gone or renamed: lets a signal handler remove it (the name must be known first, or a
  /// signal between creating and registering would leave a file behind).
  using NameRegistry = void (*)(const char* temp_path) noexcept;

  /// Checks the target (check_output_path) and creates `<target>.tmp-XXXXXX` exclusively
  /// (mode 0600), locked for as long as this object lives. Throws std::runtime_error naming the
  /// target on failure.
  explicit AtomicFile(std::string target, NameRegistry registry = nullptr);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  /// Removes the temporary file (and the files named by its suffixes) unless committed.
  ~AtomicFile();

  const std::string& temp_path() const noexcept { return temp_path_; }
  const std::string& target_path() const noexcept { return target_; }

  /// Other files the writer may create as `<temporary>SUFFIX` (SQLite's "-journal", a side
  /// database): removed with the temporary file, and by remove_dead_temporaries().
  void remove_also(std::string suffix) { sibling_suffixes_.push_back(std::move(suffix)); }

  /// Writes all of `bytes` to the temporary file at its current end; throws naming the target.
  void append(std::string_view bytes);

  /// Starts writing what the temporary file holds so far to disk, without waiting: sync() then
  /// waits only for what is left, and the disk works while the writer computes. A hint (Linux
  /// sync_file_range; nothing elsewhere): its errors show at sync().
  void start_writeback() const noexcept;

  /// Flushes the temporary file to disk and gives it the permissions of a new file (0666 minus
  /// the umask): after it, commit() only renames. Throws std::runtime_error naming the target
  /// (a full disk may only show here).
  void sync();

  /// sync() unless done, then checks again that the target is absent or a regular
  /// file and renames it onto the target. Throws std::runtime_error naming the target (the
  /// temporary file is then removed by the destructor).
  void commit();

 private:
  void remove_temporaries() noexcept;

  std::string target_;
  std::string temp_path_;
  std::vector<std::string> sibling_suffixes_;
  NameRegistry registry_ = nullptr;
  int fd_ = -1;  // open and flock'ed until commit or destruction
  bool synced_ = false;
  bool committed_ = false;
};

/// Writes `content` to `path` atomically (AtomicFile): all or nothing.
void write_file_atomically(const std::string& path, std::string_view content);

/// Removes from `folder` the temporary files of writers that died without cleaning up (killed
/// with SIGKILL, power lost): files named `NAME.tmp-XXXXXX` (six letters or digits) that are
/// regular files owned by this user, locked by no process, and marked as an AtomicFile's (the
/// extended attribute user.roadcross.temporary, where the file system keeps it), or holding a
/// GeoPackage, or empty and older than a minute (a new writer locks its file right after
/// creating it); and
/// their `-journal`/`-rows` siblings when the temporary file itself is gone. Returns the
/// removed names. Never throws (a folder that cannot be listed is left alone).
std::vector<std::string> remove_dead_temporaries(const std::string& folder);

}  // namespace roadcross::files
