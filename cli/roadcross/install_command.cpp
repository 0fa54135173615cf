// roadcross install NEW TARGET: the documented way to replace a live map (docs/embedding.md).
// A process that has TARGET open keeps reading the old file's inode; TARGET is never written in
// place (an in-place copy would change pages under a running robot's memory map: SIGBUS or
// wrong answers).
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "roadcross/mapcheck/content_hash.hpp"
#include "roadcross/mapcheck/verify.hpp"

namespace roadcross::cli {

namespace {

class InstallError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InstallError(path + ": " + what + " (" + std::strerror(errno) + ")");
}

/// A file descriptor closed on scope exit.
class Descriptor {
 public:
  explicit Descriptor(int fd) noexcept : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const noexcept { return fd_; }
  /// Closes now, reporting the error a delayed write may surface only here.
  void close_or_throw(const std::string& path) {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(path, "cannot close");
  }

 private:
  int fd_;
};

/// The temporary copy beside TARGET, removed unless renamed into place.
class TemporaryBeside {
 public:
  explicit TemporaryBeside(const std::filesystem::path& target) {
    path_ =
        (target.parent_path() / ("." + target.filename().string() + ".install-XXXXXX")).string();
    std::vector<char> name(path_.begin(), path_.end());
    name.push_back('\0');
    fd_ = ::mkstemp(name.data());
    if (fd_ < 0) fail(path_, "cannot create a temporary file beside the target");
    path_ = name.data();
  }
  TemporaryBeside(const TemporaryBeside&) = delete;
  TemporaryBeside& operator=(const TemporaryBeside&) = delete;
  ~TemporaryBeside() {
    if (fd_ >= 0) ::close(fd_);
    if (!renamed_) ::unlink(path_.c_str());
  }
  const std::string& path() const noexcept { return path_; }
  int fd() const noexcept { return fd_; }
  void close_or_throw() {
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0) fail(path_, "cannot close");
  }
  void rename_onto(const std::string& target) {
    if (::rename(path_.c_str(), target.c_str()) != 0) fail(target, "cannot rename the copy onto");
    renamed_ = true;
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool renamed_ = false;
};

void copy_all(int from, const std::string& from_path, int to, const std::string& to_path) {
  std::vector<char> buffer(1 << 20);
  for (;;) {
    const ssize_t got = ::read(from, buffer.data(), buffer.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) fail(from_path, "cannot read");
    if (got == 0) return;
    for (ssize_t done = 0; done < got;) {
      const ssize_t put = ::write(to, buffer.data() + done, static_cast<std::size_t>(got - done));
      if (put < 0 && errno == EINTR) continue;
      if (put < 0) fail(to_path, "cannot write");
      done += put;
    }
  }
}

/// TARGET may be absent (a first install) or a regular file; never a directory, device, FIFO
/// or symbolic link (rename would replace the link, not the file the robot opened).
/// Returns the mode the installed file gets: TARGET's, else NEW's.
mode_t check_target(const std::string& target, mode_t new_mode) {
  struct stat status {};
  if (::lstat(target.c_str(), &status) != 0) {
    if (errno != ENOENT) fail(target, "cannot inspect the target");
    return new_mode;
  }
  if (S_ISLNK(status.st_mode)) {
    throw InstallError(target + ": is a symbolic link; install onto the file it points to");
  }
  if (!S_ISREG(status.st_mode)) {
    throw InstallError(target + ": not a regular file; refusing to replace it");
  }
  return status.st_mode & 07777;
}

void fsync_directory(const std::filesystem::path& directory) {
  const std::string path = directory.empty() ? "." : directory.string();
  Descriptor fd(::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (fd.get() < 0) fail(path, "cannot open the directory to fsync it");
  if (::fsync(fd.get()) != 0) fail(path, "cannot fsync the directory");
}

/// Copies NEW beside TARGET, checks the copy, renames it over TARGET; returns the map_id.
std::string install(const std::string& new_path, const std::string& target,
                    const std::string& map_id) {
  Descriptor source(::open(new_path.c_str(), O_RDONLY | O_CLOEXEC));
  if (source.get() < 0) fail(new_path, "cannot open");
  struct stat source_status {};
  if (::fstat(source.get(), &source_status) != 0) fail(new_path, "cannot inspect");
  const mode_t mode = check_target(target, source_status.st_mode & 07777);
  const std::filesystem::path target_path(target);
  TemporaryBeside copy(target_path);
  copy_all(source.get(), new_path, copy.fd(), copy.path());
  if (::fchmod(copy.fd(), mode) != 0) fail(copy.path(), "cannot set the mode of");
  if (::fsync(copy.fd()) != 0) fail(copy.path(), "cannot fsync");
  copy.close_or_throw();
  // The copy itself, as it is on the target's disk, must be the map NEW is.
  const mapcheck::VerifyResult copied = mapcheck::verify_map(copy.path(), map_id);
  if (!copied.ok()) {
    throw InstallError(copy.path() + ": the copy fails verify: " + copied.problems.front());
  }
  check_target(target, mode);  // still not replaced by something else meanwhile
  copy.rename_onto(target);
  fsync_directory(target_path.parent_path());
  return map_id;
}

}  // namespace

InstallCommand::InstallCommand(CLI::App& parent) {
  app_ = parent.add_subcommand(
      "install",
      "put a verified map in place of another by copy + fsync + rename (never in place): "
      "running robots keep the old map until they reopen");
  app_->add_option("new", new_path_, "the new map (verified first; refused if it fails)")
      ->required();
  app_->add_option("target", target_path_, "the map path robots open (absent or a regular file)")
      ->required();
  app_->add_option("--expect-id", expected_id_, "refuse unless the new map's map_id is this one");
}

int InstallCommand::run() {
  if (!expected_id_.empty() && !mapcheck::is_map_id(expected_id_)) {
    std::cerr << "roadcross install: --expect-id: not a map_id (64 lower-case hex digits): "
              << expected_id_ << "\n";
    return 2;
  }
  const mapcheck::VerifyResult checked = mapcheck::verify_map(new_path_, expected_id_);
  if (!checked.ok()) {
    for (const std::string& problem : checked.problems) {
      std::cerr << "roadcross install: " << new_path_ << ": " << problem << "\n";
    }
    std::cerr << "roadcross install: " << new_path_ << " fails verify; " << target_path_
              << " left unchanged\n";
    return 1;
  }
  try {
    install(new_path_, target_path_, checked.stored_map_id);
  } catch (const InstallError& e) {
    std::cerr << "roadcross install: " << e.what() << "; " << target_path_ << " left unchanged\n";
    return 1;
  }
  std::cout << "installed " << new_path_ << " as " << target_path_ << ": map_id "
            << checked.stored_map_id << ", " << checked.segment_count << " segments\n";
  return 0;
}

}  // namespace roadcross::cli
