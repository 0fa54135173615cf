// The build's SQLite VFS (mapcheck/bulk_io_vfs.hpp) over a recording VFS of the test's own: the
// calls that reach the base VFS (offsets and sizes worked out here by hand), the bytes on disk
// (compared with what the test wrote through plain system calls or the default VFS), and a base
// VFS whose writes fail (a full disk) whose error must reach SQLite's caller.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "roadcross/mapcheck/bulk_io_vfs.hpp"
#include "roadcross/schema/sqlite.hpp"

namespace sqlite = roadcross::sqlite;

namespace {

// --- the recording base VFS ---------------------------------------------------------------------

struct Call {
  char op;  // 'r' read, 'w' write, 's' sync
  std::int64_t offset;
  int bytes;
  bool operator==(const Call&) const = default;
};

std::vector<Call> calls;   // the base VFS's reads, writes and syncs, all files, in order
bool fail_writes = false;  // base writes fail as on a full disk

struct RecordingFile {
  sqlite3_file file;
  sqlite3_file* real;
};

sqlite3_file* real_of(sqlite3_file* file) {
  return reinterpret_cast<RecordingFile*>(file)->real;
}

int rec_close(sqlite3_file* f) {
  sqlite3_file* real = real_of(f);
  const int rc = real->pMethods->xClose(real);
  sqlite3_free(real);
  return rc;
}
int rec_read(sqlite3_file* f, void* out, int n, sqlite3_int64 offset) {
  calls.push_back({'r', offset, n});
  return real_of(f)->pMethods->xRead(real_of(f), out, n, offset);
}
int rec_write(sqlite3_file* f, const void* data, int n, sqlite3_int64 offset) {
  calls.push_back({'w', offset, n});
  if (fail_writes) {
    errno = ENOSPC;
    return SQLITE_FULL;
  }
  return real_of(f)->pMethods->xWrite(real_of(f), data, n, offset);
}
int rec_truncate(sqlite3_file* f, sqlite3_int64 size) {
  return real_of(f)->pMethods->xTruncate(real_of(f), size);
}
int rec_sync(sqlite3_file* f, int flags) {
  calls.push_back({'s', 0, 0});
  return real_of(f)->pMethods->xSync(real_of(f), flags);
}
int rec_file_size(sqlite3_file* f, sqlite3_int64* size) {
  return real_of(f)->pMethods->xFileSize(real_of(f), size);
}
int rec_lock(sqlite3_file* f, int lock) {
  return real_of(f)->pMethods->xLock(real_of(f), lock);
}
int rec_unlock(sqlite3_file* f, int lock) {
  return real_of(f)->pMethods->xUnlock(real_of(f), lock);
}
int rec_check_reserved(sqlite3_file* f, int* out) {
  return real_of(f)->pMethods->xCheckReservedLock(real_of(f), out);
}
int rec_file_control(sqlite3_file* f, int op, void* arg) {
  return real_of(f)->pMethods->xFileControl(real_of(f), op, arg);
}
int rec_sector_size(sqlite3_file* f) {
  return real_of(f)->pMethods->xSectorSize(real_of(f));
}
int rec_device(sqlite3_file* f) {
  return real_of(f)->pMethods->xDeviceCharacteristics(real_of(f));
}

const sqlite3_io_methods kRecordingMethods = {1,
                                              rec_close,
                                              rec_read,
                                              rec_write,
                                              rec_truncate,
                                              rec_sync,
                                              rec_file_size,
                                              rec_lock,
                                              rec_unlock,
                                              rec_check_reserved,
                                              rec_file_control,
                                              rec_sector_size,
                                              rec_device,
                                              nullptr,
                                              nullptr,
                                              nullptr,
                                              nullptr,
                                              nullptr,
                                              nullptr};

sqlite3_vfs recording_vfs;

int rec_open(sqlite3_vfs*, const char* name, sqlite3_file* file, int flags, int* out_flags) {
  sqlite3_vfs* base = sqlite3_vfs_find(nullptr);
  auto* f = reinterpret_cast<RecordingFile*>(file);
  f->file.pMethods = nullptr;
  f->real = static_cast<sqlite3_file*>(sqlite3_malloc(base->szOsFile));
  std::memset(f->real, 0, static_cast<std::size_t>(base->szOsFile));
  const int rc = base->xOpen(base, name, f->real, flags, out_flags);
  if (rc != SQLITE_OK) {
    sqlite3_free(f->real);
    return rc;
  }
  f->file.pMethods = &kRecordingMethods;
  return SQLITE_OK;
}

/// "recording" over the default VFS (files wrapped), and "bulk-16k" (16 KiB buffers) over it.
void register_test_vfses() {
  static const bool once = [] {
    sqlite3_vfs* base = sqlite3_vfs_find(nullptr);
    recording_vfs = *base;
    recording_vfs.pNext = nullptr;
    recording_vfs.zName = "recording";
    recording_vfs.szOsFile = sizeof(RecordingFile);
    recording_vfs.xOpen = rec_open;
    sqlite3_vfs_register(&recording_vfs, 0);
    roadcross::mapcheck::register_bulk_io_vfs("bulk-16k", "recording", 16 * 1024);
    return true;
  }();
  (void)once;
}

constexpr int kPage = 4096;
constexpr int kOpenFlags = SQLITE_OPEN_MAIN_DB | SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;

/// A page of `fill` bytes.
std::vector<unsigned char> page(unsigned char fill) {
  return std::vector<unsigned char>(kPage, fill);
}

std::string temp_path(const std::string& name) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  std::filesystem::remove(path);
  return path;
}

std::vector<unsigned char> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A file opened through "bulk-16k" with the VFS's own methods (no SQLite pager).
class OpenFile {
 public:
  explicit OpenFile(const std::string& path, int flags = kOpenFlags) {
    register_test_vfses();
    vfs_ = sqlite3_vfs_find("bulk-16k");
    storage_.resize(static_cast<std::size_t>(vfs_->szOsFile) / sizeof(std::max_align_t) + 1);
    file_ = reinterpret_cast<sqlite3_file*>(storage_.data());
    int out_flags = 0;
    EXPECT_EQ(vfs_->xOpen(vfs_, path.c_str(), file_, flags, &out_flags), SQLITE_OK);
  }
  ~OpenFile() {
    if (file_->pMethods) file_->pMethods->xClose(file_);
  }
  int write(const std::vector<unsigned char>& bytes, std::int64_t offset) {
    return file_->pMethods->xWrite(file_, bytes.data(), static_cast<int>(bytes.size()), offset);
  }
  int read(std::vector<unsigned char>& out, std::int64_t offset) {
    return file_->pMethods->xRead(file_, out.data(), static_cast<int>(out.size()), offset);
  }
  sqlite3_file* file() { return file_; }

 private:
  sqlite3_vfs* vfs_;
  std::vector<std::max_align_t> storage_;
  sqlite3_file* file_;
};

}  // namespace

TEST(BulkIoVfs, ContiguousWritesGoOutTogetherAndAGapStartsANewWrite) {
  const std::string path = temp_path("bulk_io_gaps.bin");
  calls.clear();
  {
    OpenFile f(path);
    ASSERT_EQ(f.write(page(1), 0 * kPage), SQLITE_OK);
    ASSERT_EQ(f.write(page(2), 1 * kPage), SQLITE_OK);
    ASSERT_EQ(f.write(page(3), 2 * kPage), SQLITE_OK);
    EXPECT_TRUE(calls.empty());                         // all three in the buffer
    ASSERT_EQ(f.write(page(5), 4 * kPage), SQLITE_OK);  // a gap: the first three go out
    ASSERT_EQ(f.write(page(6), 5 * kPage), SQLITE_OK);
    ASSERT_EQ(f.write(page(9), 4 * kPage), SQLITE_OK);  // over a pending page: stays pending
    ASSERT_EQ(f.write(page(7), 6 * kPage), SQLITE_OK);
    ASSERT_EQ(f.write(page(8), 7 * kPage), SQLITE_OK);  // 16 KiB pending: the buffer is full
    ASSERT_EQ(f.write(page(10), 8 * kPage), SQLITE_OK);
    ASSERT_EQ(f.write(page(4), 3 * kPage), SQLITE_OK);  // backwards: the pending page goes out
    ASSERT_EQ(f.file()->pMethods->xSync(f.file(), SQLITE_SYNC_NORMAL), SQLITE_OK);
  }
  const std::vector<Call> expected = {{'w', 0, 3 * kPage},
                                      {'w', 4 * kPage, 4 * kPage},
                                      {'w', 8 * kPage, kPage},
                                      {'w', 3 * kPage, kPage},
                                      {'s', 0, 0}};
  EXPECT_EQ(calls, expected);
  std::vector<unsigned char> bytes;
  for (int fill : {1, 2, 3, 4, 9, 6, 7, 8, 10}) {
    const auto p = page(static_cast<unsigned char>(fill));
    bytes.insert(bytes.end(), p.begin(), p.end());
  }
  EXPECT_EQ(file_bytes(path), bytes);
}

TEST(BulkIoVfs, AReadOfPendingBytesWritesThemFirst) {
  const std::string path = temp_path("bulk_io_pending_read.bin");
  calls.clear();
  OpenFile f(path);
  ASSERT_EQ(f.write(page(1), 0), SQLITE_OK);
  ASSERT_EQ(f.write(page(2), kPage), SQLITE_OK);
  std::vector<unsigned char> out(100);
  ASSERT_EQ(f.read(out, kPage + 10), SQLITE_OK);
  EXPECT_EQ(out, std::vector<unsigned char>(100, 2));
  ASSERT_GE(calls.size(), 2u);
  EXPECT_EQ(calls[0], (Call{'w', 0, 2 * kPage}));
  EXPECT_EQ(calls[1].op, 'r');
  // The size counts pending bytes without writing them.
  calls.clear();
  ASSERT_EQ(f.write(page(3), 2 * kPage), SQLITE_OK);
  sqlite3_int64 size = 0;
  ASSERT_EQ(f.file()->pMethods->xFileSize(f.file(), &size), SQLITE_OK);
  EXPECT_EQ(size, 3 * kPage);
  EXPECT_TRUE(calls.empty());
}

TEST(BulkIoVfs, AFailedBaseWriteIsTheErrorOfTheCallThatNeededIt) {
  const std::string path = temp_path("bulk_io_fail.bin");
  calls.clear();
  OpenFile f(path);
  fail_writes = true;
  EXPECT_EQ(f.write(page(1), 0), SQLITE_OK);  // buffered
  EXPECT_EQ(f.file()->pMethods->xSync(f.file(), SQLITE_SYNC_NORMAL), SQLITE_FULL);
  EXPECT_EQ(f.write(page(1), 0), SQLITE_OK);
  EXPECT_EQ(f.file()->pMethods->xUnlock(f.file(), SQLITE_LOCK_NONE), SQLITE_FULL);
  EXPECT_EQ(f.write(page(1), 0), SQLITE_OK);
  EXPECT_EQ(f.write(page(2), 5 * kPage), SQLITE_FULL);  // not contiguous: the first goes out
  fail_writes = false;
  EXPECT_EQ(f.file()->pMethods->xSync(f.file(), SQLITE_SYNC_NORMAL), SQLITE_OK);
}

/// The build's settings (no journal, no sync), rows inserted and committed; "x" a blob column.
void fill_database(sqlite::Database& db, int rows) {
  db.exec("PRAGMA page_size = 4096");
  db.exec("PRAGMA journal_mode = OFF");
  db.exec("PRAGMA synchronous = OFF");
  db.exec("PRAGMA cache_size = 20");  // small: pages are spilled during the inserts too
  db.exec("BEGIN");
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x BLOB)");
  db.exec("WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < " +
          std::to_string(rows) + ") INSERT INTO t SELECT i, zeroblob(i % 700) " +
          "|| CAST(i AS BLOB) FROM n");
  db.exec("COMMIT");
}

TEST(BulkIoVfs, SqliteWritesTheSameFileAsThroughTheDefaultVfs) {
  register_test_vfses();
  const std::string plain = temp_path("bulk_io_plain.sqlite");
  const std::string bulk = temp_path("bulk_io_bulk.sqlite");
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  {
    sqlite::Database db(plain, flags);
    fill_database(db, 5000);
  }
  calls.clear();
  {
    sqlite::Database db(bulk, flags, "bulk-16k");
    fill_database(db, 5000);
  }
  const auto expected = file_bytes(plain);
  ASSERT_GT(expected.size(), 100u * kPage);
  EXPECT_EQ(file_bytes(bulk), expected);
  // Far fewer base writes than pages, none larger than the buffer.
  std::size_t writes = 0;
  for (const Call& c : calls) {
    if (c.op == 'w') {
      ++writes;
      EXPECT_LE(c.bytes, 16 * 1024);
    }
  }
  EXPECT_LT(writes, expected.size() / kPage / 2);
}

TEST(BulkIoVfs, AFullDiskFailsTheCommit) {
  register_test_vfses();
  const std::string path = temp_path("bulk_io_full.sqlite");
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, "bulk-16k");
  db.exec("PRAGMA journal_mode = OFF");
  db.exec("PRAGMA synchronous = OFF");
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x BLOB)");
  db.exec("BEGIN");
  db.exec(
      "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 10) "
      "INSERT INTO t SELECT i, zeroblob(100) FROM n");
  fail_writes = true;
  try {
    db.exec("COMMIT");
    ADD_FAILURE() << "the commit succeeded though no page reached the file";
  } catch (const sqlite::sqlite_error& e) {
    EXPECT_EQ(e.code() & 0xff, SQLITE_FULL) << e.what();
  }
  fail_writes = false;
}

TEST(BulkIoVfs, SequentialReadsReadAheadAndSeeTheFileAfterALockCycle) {
  const std::string path = temp_path("bulk_io_read.bin");
  std::vector<unsigned char> content;
  for (int i = 0; i < 40; ++i) {
    const auto p = page(static_cast<unsigned char>(i + 1));
    content.insert(content.end(), p.begin(), p.end());
  }
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(content.data()),
              static_cast<std::streamsize>(content.size()));
  }
  calls.clear();
  OpenFile f(path, SQLITE_OPEN_MAIN_DB | SQLITE_OPEN_READONLY);
  ASSERT_EQ(f.file()->pMethods->xLock(f.file(), SQLITE_LOCK_SHARED), SQLITE_OK);
  std::vector<unsigned char> out(kPage);
  for (int i = 0; i < 40; ++i) {
    ASSERT_EQ(f.read(out, std::int64_t{i} * kPage), SQLITE_OK);
    EXPECT_EQ(out, page(static_cast<unsigned char>(i + 1))) << "page " << i;
  }
  // Page 0 directly (no read before it to continue), then windows of 16 KiB (the buffer's size)
  // from each sequential miss: pages 1-4, 5-8, ... 33-36, then 37-40 read short (the file ends 3
  // pages in) and read again up to the end.
  std::vector<Call> expected = {{'r', 0, kPage}};
  for (int first = 1; first < 37; first += 4) expected.push_back({'r', first * kPage, 4 * kPage});
  expected.push_back({'r', 37 * kPage, 4 * kPage});
  expected.push_back({'r', 37 * kPage, 3 * kPage});
  EXPECT_EQ(calls, expected);
  // Another process changes page 3; the next transaction (a lock from none) must see it.
  {
    const int fd = ::open(path.c_str(), O_WRONLY);
    ASSERT_GE(fd, 0);
    const auto changed = page(99);
    ASSERT_EQ(::pwrite(fd, changed.data(), changed.size(), 3 * kPage), kPage);
    ::close(fd);
  }
  ASSERT_EQ(f.read(out, 2 * kPage), SQLITE_OK);  // still the old transaction: the window
  ASSERT_EQ(f.file()->pMethods->xUnlock(f.file(), SQLITE_LOCK_NONE), SQLITE_OK);
  ASSERT_EQ(f.file()->pMethods->xLock(f.file(), SQLITE_LOCK_SHARED), SQLITE_OK);
  ASSERT_EQ(f.read(out, 3 * kPage), SQLITE_OK);
  EXPECT_EQ(out, page(99));
}

TEST(BulkIoVfs, ReadsOfADatabaseGiveTheSameRows) {
  register_test_vfses();
  const std::string path = temp_path("bulk_io_rows.sqlite");
  {
    sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
    fill_database(db, 5000);
  }
  const auto sum = [&](const char* vfs) {
    sqlite::Database db(path, SQLITE_OPEN_READONLY, vfs);
    auto query = db.prepare("SELECT sum(length(x)), sum(id * unicode(hex(x))) FROM t");
    EXPECT_TRUE(query.step());
    return query.column_text(0) + " " + query.column_text(1);
  };
  calls.clear();
  const std::string through_bulk = sum("bulk-16k");
  EXPECT_EQ(through_bulk, sum(nullptr));
  EXPECT_LT(calls.size(), std::filesystem::file_size(path) / kPage / 2);
}

TEST(BulkIoVfs, ACacheFlushInsideATransactionWritesThePages) {
  register_test_vfses();
  const std::string path = temp_path("bulk_io_cacheflush.sqlite");
  sqlite::Database db(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, "bulk-16k");
  db.exec("PRAGMA page_size = 4096");
  db.exec("PRAGMA journal_mode = OFF");
  db.exec("PRAGMA synchronous = OFF");
  db.exec("BEGIN");
  db.exec("CREATE TABLE t (id INTEGER PRIMARY KEY, x BLOB)");
  db.exec(
      "WITH RECURSIVE n(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM n WHERE i < 1000) "
      "INSERT INTO t SELECT i, zeroblob(500) FROM n");
  calls.clear();
  EXPECT_EQ(sqlite3_db_cacheflush(db.handle()), SQLITE_OK) << sqlite3_errmsg(db.handle());
  db.exec("COMMIT");
}

TEST(BulkIoVfs, NoBaseCallTakesMoreThanTheUnixVfsCan) {
  // The unix VFS writes only the low 17 bits of a count: a 1 MiB buffer is cut to 128 KiB - 1
  // (31 pages of 4 KiB).
  register_test_vfses();
  roadcross::mapcheck::register_bulk_io_vfs("bulk-1m", "recording", 1 << 20);
  const std::string path = temp_path("bulk_io_large.sqlite");
  const int flags = SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  const std::string plain = temp_path("bulk_io_large_plain.sqlite");
  {
    sqlite::Database db(plain, flags);
    fill_database(db, 20000);
  }
  calls.clear();
  {
    sqlite::Database db(path, flags, "bulk-1m");
    fill_database(db, 20000);
  }
  EXPECT_EQ(file_bytes(path), file_bytes(plain));
  bool some_full = false;
  for (const Call& c : calls) {
    EXPECT_LE(c.bytes, 0x1ffff);
    some_full = some_full || c.bytes == 31 * kPage;
  }
  EXPECT_TRUE(some_full);
}
