#include "roadcross/files/atomic_file.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <random>
#include <stdexcept>

namespace roadcross::files {

namespace {

constexpr std::string_view kTempMarker = ".tmp-";
constexpr std::size_t kTempLetters = 6;
constexpr std::string_view kSiblingSuffixes[] = {"-journal", "-rows"};
// An empty temporary file is only provably dead once its writer had time to lock it.
constexpr std::time_t kEmptyTemporaryAge_s = 60;

std::string folder_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string errno_text() {
  return std::strerror(errno);
}

[[noreturn]] void fail(const std::string& path, const std::string& why) {
  throw std::runtime_error("cannot write " + path + ": " + why);
}

/// What kind of thing a non-regular file is, for the error message.
std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISLNK(mode)) return "a symbolic link (give the path it points to)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

/// Throws unless nothing or a regular file is at `path` (lstat: a link is not followed).
void check_replaceable(const std::string& path) {
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) {
    if (errno == ENOENT) return;
    fail(path, errno_text());
  }
  if (!S_ISREG(st.st_mode)) fail(path, "it is " + kind_of(st.st_mode) + ", not a regular file");
}

bool is_temp_letter(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9');
}

/// Whether `name` is `X.tmp-XXXXXX` (the temporary file itself, no sibling suffix).
bool is_temporary_name(std::string_view name) {
  const std::size_t tail = kTempMarker.size() + kTempLetters;
  if (name.size() <= tail) return false;
  const std::string_view end = name.substr(name.size() - tail);
  if (end.substr(0, kTempMarker.size()) != kTempMarker) return false;
  for (char c : end.substr(kTempMarker.size())) {
    if (!is_temp_letter(c)) return false;
  }
  return true;
}

/// Whether the file starts like a GeoPackage: SQLite's header and application_id "GPKG".
bool holds_geopackage(int fd) {
  unsigned char header[72];
  if (::pread(fd, header, sizeof header, 0) != static_cast<ssize_t>(sizeof header)) return false;
  return std::memcmp(header, "SQLite format 3", 16) == 0 &&
         std::memcmp(header + 68, "GPKG", 4) == 0;
}

/// The extended attribute that marks a file as an AtomicFile's temporary (where the file system
/// has user attributes): what proves a file nobody locks to be a dead writer's.
constexpr const char* kMarkerAttribute = "user.roadcross.temporary";

bool has_marker(int fd) {
  char value[2];
  return ::fgetxattr(fd, kMarkerAttribute, value, sizeof value) == 1 && value[0] == '1';
}

/// Whether the temporary file `path` is provably a dead writer's: see remove_dead_temporaries.
bool is_dead_temporary(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return false;
  struct stat st {};
  bool dead = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid() &&
              ::flock(fd, LOCK_EX | LOCK_NB) == 0;
  if (dead) {
    const bool old_and_empty =
        st.st_size == 0 && std::time(nullptr) - st.st_mtime >= kEmptyTemporaryAge_s;
    dead = old_and_empty || has_marker(fd) || holds_geopackage(fd);
  }
  ::close(fd);  // drops the probe's lock
  return dead;
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0;
}

}  // namespace

void check_output_path(const std::string& path) {
  if (path.empty()) throw std::runtime_error("no output path given (an empty name)");
  const std::string folder = folder_of(path);
  struct stat st {};
  if (::stat(folder.c_str(), &st) != 0) fail(path, "folder " + folder + " does not exist");
  if (!S_ISDIR(st.st_mode)) {
    fail(path, folder + " is not a folder");
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    fail(path, "folder " + folder + " is not writable (" + errno_text() + ")");
  }
  check_replaceable(path);
}

AtomicFile::AtomicFile(std::string target, NameRegistry registry)
    : target_(std::move(target)), registry_(registry) {
  check_output_path(target_);
  // Not mkstemp: a signal handler must know the name before the file exists, so the name is
  // chosen and registered first, then created exclusively.
  std::random_device entropy;
  constexpr char kLetters[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  for (int attempt = 0; attempt < 100; ++attempt) {
    std::string candidate = target_ + std::string(kTempMarker);
    for (std::size_t i = 0; i < kTempLetters; ++i) {
      candidate += kLetters[entropy() % (sizeof kLetters - 1)];
    }
    if (registry_) registry_(candidate.c_str());
    fd_ = ::open(candidate.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd_ >= 0) {
      temp_path_ = std::move(candidate);
      // Marked as ours (ignored where the file system has no user attributes: the GeoPackage
      // header then proves it).
      (void)::fsetxattr(fd_, kMarkerAttribute, "1", 1, 0);
      if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
        const std::string why = errno_text();
        remove_temporaries();
        fail(target_, "cannot lock the temporary file (" + why + ")");
      }
      return;
    }
    const int open_errno = errno;
    if (registry_) registry_(nullptr);
    if (open_errno != EEXIST) {
      fail(target_, "cannot create the temporary file " + candidate + " (" +
                        std::strerror(open_errno) + ")");
    }
  }
  fail(target_, "100 temporary names taken");
}

AtomicFile::~AtomicFile() {
  if (!committed_) remove_temporaries();
}

void AtomicFile::remove_temporaries() noexcept {
  if (!temp_path_.empty()) {
    ::unlink(temp_path_.c_str());
    for (const std::string& suffix : sibling_suffixes_) ::unlink((temp_path_ + suffix).c_str());
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  // Only now: a signal before this line removes what is already gone, which is harmless.
  if (registry_) registry_(nullptr);
}

void AtomicFile::append(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail(target_, n < 0 ? errno_text() : "no space left on device");
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void AtomicFile::start_writeback() const noexcept {
#if defined(__linux__)
  ::sync_file_range(fd_, 0, 0, SYNC_FILE_RANGE_WRITE);
#endif
}

void AtomicFile::sync() {
  // A full disk may only show when the data reach it (delayed allocation, NFS): fsync first,
  // so that a failure leaves the old file, not a truncated new one.
  if (::fsync(fd_) != 0) fail(target_, errno_text());
  // The temporary file is created 0600; an output is meant to be shared like any new file.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  if (::fchmod(fd_, 0666 & ~mask) != 0) fail(target_, errno_text());
  synced_ = true;
}

void AtomicFile::commit() {
  if (!synced_) sync();
  // Again just before the rename: something may have appeared at the target meanwhile.
  check_replaceable(target_);
  if (std::rename(temp_path_.c_str(), target_.c_str()) != 0) {
    fail(target_, "cannot move the finished file into place (" + errno_text() + ")");
  }
  committed_ = true;
  for (const std::string& suffix : sibling_suffixes_) ::unlink((temp_path_ + suffix).c_str());
  ::close(fd_);
  fd_ = -1;
  if (registry_) registry_(nullptr);
}

void write_file_atomically(const std::string& path, std::string_view content) {
  AtomicFile file(path);
  file.append(content);
  file.commit();
}

std::vector<std::string> remove_dead_temporaries(const std::string& folder) {
  std::vector<std::string> removed;
  DIR* dir = ::opendir(folder.c_str());
  if (!dir) return removed;
  std::vector<std::string> names;
  while (const dirent* entry = ::readdir(dir)) names.emplace_back(entry->d_name);
  ::closedir(dir);
  const std::string prefix = folder == "/" ? "/" : folder + "/";
  for (const std::string& name : names) {
    const std::string path = prefix + name;
    if (is_temporary_name(name)) {
      if (!is_dead_temporary(path) || ::unlink(path.c_str()) != 0) continue;
      removed.push_back(path);
      for (std::string_view suffix : kSiblingSuffixes) {
        const std::string sibling = path + std::string(suffix);
        if (::unlink(sibling.c_str()) == 0) removed.push_back(sibling);
      }
      continue;
    }
    // A sibling whose temporary file is gone (its writer died between removing the two).
    for (std::string_view suffix : kSiblingSuffixes) {
      if (name.size() <= suffix.size() || !name.ends_with(suffix)) continue;
      const std::string base = name.substr(0, name.size() - suffix.size());
      if (!is_temporary_name(base) || exists(prefix + base)) continue;
      struct stat st {};
      if (::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && st.st_uid == ::geteuid() &&
          ::unlink(path.c_str()) == 0) {
        removed.push_back(path);
      }
    }
  }
  return removed;
}

}  // namespace roadcross::files
