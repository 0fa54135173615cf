#include "roadcross/mapcheck/bulk_io_vfs.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>

namespace roadcross::mapcheck {
namespace {

/// One registered VFS: SQLite's struct (first: SQLite passes a pointer to it) and what wraps.
struct BulkVfs {
  sqlite3_vfs vfs{};
  sqlite3_vfs* base = nullptr;
  std::size_t buffer_bytes = 0;
  std::string name;
};

BulkVfs& bulk_of(sqlite3_vfs* vfs) {
  return *reinterpret_cast<BulkVfs*>(vfs);
}

/// The first read-ahead fills this many bytes, each sequential miss after it twice the last.
constexpr std::size_t kFirstReadAheadBytes = 32 * 1024;

/// The most bytes one read or write of SQLite's unix VFS takes: its seekAndWriteFd keeps the low
/// 17 bits of the count (a larger write silently writes less and reports SQLITE_FULL), its reads
/// assert the same (SQLite's own calls never pass a page, at most 64 KiB).
constexpr std::size_t kMaxBaseCallBytes = 0x1ffff;

/// One open file: SQLite's struct first; the base VFS's file follows this struct in the same
/// allocation (sqlite3_vfs::szOsFile covers both).
struct BulkFile {
  sqlite3_file file{};
  sqlite3_file* base = nullptr;
  std::size_t buffer_bytes = 0;

  /// Bytes written by SQLite, not yet by the base VFS: [pending_offset, + pending_bytes).
  std::unique_ptr<unsigned char[]> write_buffer;
  sqlite3_int64 pending_offset = 0;
  std::size_t pending_bytes = 0;

  /// The file's bytes [ahead_offset, + ahead_bytes) as read (nothing written over them since).
  std::unique_ptr<unsigned char[]> read_buffer;
  sqlite3_int64 ahead_offset = 0;
  std::size_t ahead_bytes = 0;
  /// Where the last read ended: a read starting there is sequential.
  sqlite3_int64 next_read_offset = -1;
  std::size_t window_bytes = 0;
  bool read_ahead_allowed = true;
  int lock = SQLITE_LOCK_NONE;

  bool pending_overlaps(sqlite3_int64 offset, sqlite3_int64 bytes) const {
    return pending_bytes > 0 &&
           offset < pending_offset + static_cast<sqlite3_int64>(pending_bytes) &&
           pending_offset < offset + bytes;
  }
  void drop_read_ahead() { ahead_bytes = 0; }

  /// Hands the pending bytes to the base VFS. They are gone either way: on failure SQLite gets
  /// the base VFS's error (and the errno it left) for the call that needed them written.
  int flush() {
    if (pending_bytes == 0) return SQLITE_OK;
    const std::size_t bytes = pending_bytes;
    pending_bytes = 0;
    return base->pMethods->xWrite(base, write_buffer.get(), static_cast<int>(bytes),
                                  pending_offset);
  }
};

BulkFile& bulk_of(sqlite3_file* file) {
  return *reinterpret_cast<BulkFile*>(file);
}

/// The base VFS's file sits after BulkFile, aligned for any of its members.
constexpr std::size_t kBaseFileOffset = (sizeof(BulkFile) + alignof(std::max_align_t) - 1) /
                                        alignof(std::max_align_t) * alignof(std::max_align_t);

// --- the file's methods --------------------------------------------------------------------------

int bulk_close(sqlite3_file* file) {
  BulkFile& f = bulk_of(file);
  // SQLite commits with a lock change and a file control (both write the buffer out first), so
  // a close finds bytes here only after an error, on a file the build then removes.
  const int flushed = f.flush();
  const int closed = f.base->pMethods->xClose(f.base);
  f.~BulkFile();
  return flushed != SQLITE_OK ? flushed : closed;
}

int direct_read(BulkFile& f, void* out, int bytes, sqlite3_int64 offset) {
  const int rc = f.base->pMethods->xRead(f.base, out, bytes, offset);
  if (rc == SQLITE_OK) f.next_read_offset = offset + bytes;
  return rc;
}

int bulk_read(sqlite3_file* file, void* out, int bytes, sqlite3_int64 offset) {
  BulkFile& f = bulk_of(file);
  if (f.pending_overlaps(offset, bytes)) {
    if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  }
  const auto wanted = static_cast<std::size_t>(bytes);
  if (f.ahead_bytes > 0 && offset >= f.ahead_offset &&
      offset + bytes <= f.ahead_offset + static_cast<sqlite3_int64>(f.ahead_bytes)) {
    std::memcpy(out, f.read_buffer.get() + (offset - f.ahead_offset), wanted);
    f.next_read_offset = offset + bytes;
    return SQLITE_OK;
  }
  const bool sequential = offset == f.next_read_offset;
  if (!sequential || !f.read_ahead_allowed || wanted > f.buffer_bytes) {
    f.window_bytes = 0;  // a jump: start small again
    return direct_read(f, out, bytes, offset);
  }
  if (!f.read_buffer) {
    f.read_buffer.reset(new (std::nothrow) unsigned char[f.buffer_bytes]);
    if (!f.read_buffer) return direct_read(f, out, bytes, offset);
  }
  f.window_bytes =
      std::min(f.buffer_bytes, f.window_bytes == 0 ? kFirstReadAheadBytes : f.window_bytes * 2);
  std::size_t fill_bytes = std::max(f.window_bytes, wanted);
  // What is read ahead must be what the file will hold: pending bytes in its range first.
  if (f.pending_overlaps(offset, static_cast<sqlite3_int64>(fill_bytes))) {
    if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  }
  f.ahead_bytes = 0;
  int rc =
      f.base->pMethods->xRead(f.base, f.read_buffer.get(), static_cast<int>(fill_bytes), offset);
  if (rc == SQLITE_IOERR_SHORT_READ) {
    // The window runs past the end of the file: read ahead up to the end, if the request ends
    // before it (else the base VFS answers the request itself, zero-filling past the end).
    sqlite3_int64 size = 0;
    rc = f.base->pMethods->xFileSize(f.base, &size);
    if (rc != SQLITE_OK) return rc;
    if (size - offset < bytes) return direct_read(f, out, bytes, offset);
    fill_bytes = static_cast<std::size_t>(std::min<sqlite3_int64>(size - offset, fill_bytes));
    rc = f.base->pMethods->xRead(f.base, f.read_buffer.get(), static_cast<int>(fill_bytes), offset);
  }
  if (rc != SQLITE_OK) return rc;
  f.ahead_offset = offset;
  f.ahead_bytes = fill_bytes;
  std::memcpy(out, f.read_buffer.get(), wanted);
  f.next_read_offset = offset + bytes;
  return SQLITE_OK;
}

int bulk_write(sqlite3_file* file, const void* data, int bytes, sqlite3_int64 offset) {
  BulkFile& f = bulk_of(file);
  const auto size = static_cast<std::size_t>(bytes);
  if (f.ahead_bytes > 0 && offset < f.ahead_offset + static_cast<sqlite3_int64>(f.ahead_bytes) &&
      f.ahead_offset < offset + bytes) {
    f.drop_read_ahead();
  }
  if (f.pending_bytes > 0) {
    const sqlite3_int64 pending_end =
        f.pending_offset + static_cast<sqlite3_int64>(f.pending_bytes);
    if (offset >= f.pending_offset && offset + bytes <= pending_end) {  // over pending bytes
      std::memcpy(f.write_buffer.get() + (offset - f.pending_offset), data, size);
      return SQLITE_OK;
    }
    if (offset == pending_end && f.pending_bytes + size <= f.buffer_bytes) {  // continues them
      std::memcpy(f.write_buffer.get() + f.pending_bytes, data, size);
      f.pending_bytes += size;
      return SQLITE_OK;
    }
    if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  }
  if (size <= f.buffer_bytes && !f.write_buffer) {
    f.write_buffer.reset(new (std::nothrow) unsigned char[f.buffer_bytes]);
  }
  if (size > f.buffer_bytes || !f.write_buffer) {
    return f.base->pMethods->xWrite(f.base, data, bytes, offset);
  }
  std::memcpy(f.write_buffer.get(), data, size);
  f.pending_offset = offset;
  f.pending_bytes = size;
  return SQLITE_OK;
}

int bulk_truncate(sqlite3_file* file, sqlite3_int64 size) {
  BulkFile& f = bulk_of(file);
  if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  f.drop_read_ahead();
  return f.base->pMethods->xTruncate(f.base, size);
}

int bulk_sync(sqlite3_file* file, int flags) {
  BulkFile& f = bulk_of(file);
  if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  return f.base->pMethods->xSync(f.base, flags);
}

int bulk_file_size(sqlite3_file* file, sqlite3_int64* size) {
  BulkFile& f = bulk_of(file);
  const int rc = f.base->pMethods->xFileSize(f.base, size);
  // Pending bytes only ever extend the file (a truncation writes them out first).
  if (rc == SQLITE_OK && f.pending_bytes > 0) {
    *size = std::max(*size, f.pending_offset + static_cast<sqlite3_int64>(f.pending_bytes));
  }
  return rc;
}

/// A lock change ends or starts a transaction: the bytes are written before another connection
/// may look, and what was read ahead before holding a lock may have changed since.
void after_lock_change(BulkFile& f, int new_lock) {
  if (f.lock == SQLITE_LOCK_NONE || new_lock == SQLITE_LOCK_NONE) f.drop_read_ahead();
  f.lock = new_lock;
}

int bulk_lock(sqlite3_file* file, int lock) {
  BulkFile& f = bulk_of(file);
  if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  const int rc = f.base->pMethods->xLock(f.base, lock);
  if (rc == SQLITE_OK) after_lock_change(f, lock);
  return rc;
}

int bulk_unlock(sqlite3_file* file, int lock) {
  BulkFile& f = bulk_of(file);
  if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  const int rc = f.base->pMethods->xUnlock(f.base, lock);
  if (rc == SQLITE_OK) after_lock_change(f, lock);
  return rc;
}

int bulk_check_reserved_lock(sqlite3_file* file, int* reserved) {
  BulkFile& f = bulk_of(file);
  return f.base->pMethods->xCheckReservedLock(f.base, reserved);
}

int bulk_file_control(sqlite3_file* file, int op, void* argument) {
  BulkFile& f = bulk_of(file);
  // SQLITE_FCNTL_SYNC (every commit, even with synchronous = OFF) and the rest: the base VFS
  // may act on the file. Not the size hint: SQLite gives one before each page it spills when its
  // cache is full (the side connection's small cache), and it does not touch written bytes.
  if (op != SQLITE_FCNTL_SIZE_HINT) {
    if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  }
  return f.base->pMethods->xFileControl(f.base, op, argument);
}

int bulk_sector_size(sqlite3_file* file) {
  BulkFile& f = bulk_of(file);
  return f.base->pMethods->xSectorSize(f.base);
}

int bulk_device_characteristics(sqlite3_file* file) {
  BulkFile& f = bulk_of(file);
  return f.base->pMethods->xDeviceCharacteristics(f.base);
}

// WAL mode's shared memory (version 2 of the methods). A WAL reader keeps its SHARED lock
// across transactions and another connection's checkpoint writes the file meanwhile: no
// read-ahead on such a file.
int bulk_shm_map(sqlite3_file* file, int region, int region_bytes, int extend,
                 void volatile** memory) {
  BulkFile& f = bulk_of(file);
  f.read_ahead_allowed = false;
  f.drop_read_ahead();
  return f.base->pMethods->xShmMap(f.base, region, region_bytes, extend, memory);
}

int bulk_shm_lock(sqlite3_file* file, int offset, int n, int flags) {
  BulkFile& f = bulk_of(file);
  if (const int rc = f.flush(); rc != SQLITE_OK) return rc;
  return f.base->pMethods->xShmLock(f.base, offset, n, flags);
}

void bulk_shm_barrier(sqlite3_file* file) {
  BulkFile& f = bulk_of(file);
  f.base->pMethods->xShmBarrier(f.base);
}

int bulk_shm_unmap(sqlite3_file* file, int delete_flag) {
  BulkFile& f = bulk_of(file);
  return f.base->pMethods->xShmUnmap(f.base, delete_flag);
}

// Version 3 (xFetch: memory-mapped pages) is not offered: SQLite then reads through xRead, which
// sees the pending bytes. Version 1 for a base file without WAL's shared memory.
constexpr sqlite3_io_methods methods_of_version(int version) {
  const bool shm = version >= 2;
  return {version,
          bulk_close,
          bulk_read,
          bulk_write,
          bulk_truncate,
          bulk_sync,
          bulk_file_size,
          bulk_lock,
          bulk_unlock,
          bulk_check_reserved_lock,
          bulk_file_control,
          bulk_sector_size,
          bulk_device_characteristics,
          shm ? bulk_shm_map : nullptr,
          shm ? bulk_shm_lock : nullptr,
          shm ? bulk_shm_barrier : nullptr,
          shm ? bulk_shm_unmap : nullptr,
          nullptr,
          nullptr};
}
constexpr sqlite3_io_methods kMethodsV1 = methods_of_version(1);
constexpr sqlite3_io_methods kMethodsV2 = methods_of_version(2);

// --- the VFS's methods: the base VFS's, with files wrapped ---------------------------------------

int bulk_open(sqlite3_vfs* vfs, const char* name, sqlite3_file* file, int flags, int* out_flags) {
  const BulkVfs& v = bulk_of(vfs);
  auto* f = new (file) BulkFile();
  f->base = reinterpret_cast<sqlite3_file*>(reinterpret_cast<char*>(file) + kBaseFileOffset);
  f->buffer_bytes = v.buffer_bytes;
  const int rc = v.base->xOpen(v.base, name, f->base, flags, out_flags);
  if (rc != SQLITE_OK || f->base->pMethods == nullptr) {
    f->~BulkFile();
    file->pMethods = nullptr;  // SQLite then does not call xClose
    return rc != SQLITE_OK ? rc : SQLITE_CANTOPEN;
  }
  f->file.pMethods = f->base->pMethods->iVersion >= 2 ? &kMethodsV2 : &kMethodsV1;
  return SQLITE_OK;
}

int bulk_delete(sqlite3_vfs* vfs, const char* name, int sync_dir) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xDelete(base, name, sync_dir);
}

int bulk_access(sqlite3_vfs* vfs, const char* name, int flags, int* result) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xAccess(base, name, flags, result);
}

int bulk_full_pathname(sqlite3_vfs* vfs, const char* name, int out_bytes, char* out) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xFullPathname(base, name, out_bytes, out);
}

void* bulk_dl_open(sqlite3_vfs* vfs, const char* name) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xDlOpen(base, name);
}

void bulk_dl_error(sqlite3_vfs* vfs, int bytes, char* message) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  base->xDlError(base, bytes, message);
}

void (*bulk_dl_sym(sqlite3_vfs* vfs, void* handle, const char* symbol))(void) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xDlSym(base, handle, symbol);
}

void bulk_dl_close(sqlite3_vfs* vfs, void* handle) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  base->xDlClose(base, handle);
}

int bulk_randomness(sqlite3_vfs* vfs, int bytes, char* out) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xRandomness(base, bytes, out);
}

int bulk_sleep(sqlite3_vfs* vfs, int microseconds) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xSleep(base, microseconds);
}

int bulk_current_time(sqlite3_vfs* vfs, double* julian_day) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xCurrentTime(base, julian_day);
}

int bulk_get_last_error(sqlite3_vfs* vfs, int bytes, char* message) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xGetLastError ? base->xGetLastError(base, bytes, message) : 0;
}

int bulk_current_time_int64(sqlite3_vfs* vfs, sqlite3_int64* julian_day_ms) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xCurrentTimeInt64(base, julian_day_ms);
}

int bulk_set_system_call(sqlite3_vfs* vfs, const char* name, sqlite3_syscall_ptr call) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xSetSystemCall(base, name, call);
}

sqlite3_syscall_ptr bulk_get_system_call(sqlite3_vfs* vfs, const char* name) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xGetSystemCall(base, name);
}

const char* bulk_next_system_call(sqlite3_vfs* vfs, const char* name) {
  sqlite3_vfs* base = bulk_of(vfs).base;
  return base->xNextSystemCall(base, name);
}

/// Registered VFSes live as long as the process (SQLite keeps pointers to them): never
/// destroyed, not even at exit.
std::deque<BulkVfs>& registered() {
  static auto* vfses = new std::deque<BulkVfs>;
  return *vfses;
}

}  // namespace

void register_bulk_io_vfs(const std::string& name, const std::string& base_name,
                          std::size_t buffer_bytes) {
  static std::mutex mutex;
  const std::lock_guard<std::mutex> lock(mutex);
  for (const BulkVfs& v : registered()) {
    if (v.name == name) return;
  }
  sqlite3_vfs* base = sqlite3_vfs_find(base_name.empty() ? nullptr : base_name.c_str());
  if (base == nullptr) throw std::runtime_error("no SQLite VFS named " + base_name);
  BulkVfs& v = registered().emplace_back();
  v.base = base;
  v.buffer_bytes = std::clamp<std::size_t>(buffer_bytes, 1, kMaxBaseCallBytes);
  v.name = name;
  sqlite3_vfs& s = v.vfs;
  s.iVersion = std::min(base->iVersion, 3);
  s.szOsFile = static_cast<int>(kBaseFileOffset) + base->szOsFile;
  s.mxPathname = base->mxPathname;
  s.zName = v.name.c_str();
  s.xOpen = bulk_open;
  s.xDelete = bulk_delete;
  s.xAccess = bulk_access;
  s.xFullPathname = bulk_full_pathname;
  s.xDlOpen = base->xDlOpen ? bulk_dl_open : nullptr;
  s.xDlError = base->xDlError ? bulk_dl_error : nullptr;
  s.xDlSym = base->xDlSym ? bulk_dl_sym : nullptr;
  s.xDlClose = base->xDlClose ? bulk_dl_close : nullptr;
  s.xRandomness = bulk_randomness;
  s.xSleep = bulk_sleep;
  s.xCurrentTime = bulk_current_time;
  s.xGetLastError = bulk_get_last_error;
  if (s.iVersion >= 2) s.xCurrentTimeInt64 = bulk_current_time_int64;
  if (s.iVersion >= 3) {
    s.xSetSystemCall = base->xSetSystemCall ? bulk_set_system_call : nullptr;
    s.xGetSystemCall = base->xGetSystemCall ? bulk_get_system_call : nullptr;
    s.xNextSystemCall = base->xNextSystemCall ? bulk_next_system_call : nullptr;
  }
  if (const int rc = sqlite3_vfs_register(&s, 0); rc != SQLITE_OK) {
    registered().pop_back();
    throw std::runtime_error("cannot register the SQLite VFS " + name + ": " + sqlite3_errstr(rc));
  }
}

const char* bulk_io_vfs() {
  static constexpr const char* kName = "roadcross-bulk-io";
  // 124 KiB: 31 pages of 4 KiB a call, the most under the unix VFS's limit (kMaxBaseCallBytes).
  static std::once_flag once;
  std::call_once(once, [] { register_bulk_io_vfs(kName, "", 124 * 1024); });
  return kName;
}

}  // namespace roadcross::mapcheck
