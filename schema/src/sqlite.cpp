#include "roadcross/schema/sqlite.hpp"

#include <cstring>

namespace roadcross::sqlite {
namespace {

/// SQLite's message, plus the operating system's reason for I/O errors ("File too large",
/// "No space left on device") which SQLite's own text ("disk I/O error") hides.
std::string describe(sqlite3* db, int rc) {
  std::string message = db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  const int primary = rc & 0xff;
  if (db && (primary == SQLITE_IOERR || primary == SQLITE_FULL || primary == SQLITE_CANTOPEN)) {
    const int os_error = sqlite3_system_errno(db);
    if (os_error != 0) message += std::string(": ") + std::strerror(os_error);
  }
  return message;
}

}  // namespace

Database::Database(const std::string& path, int flags, const char* vfs) {
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, vfs);
  if (rc != SQLITE_OK) {
    std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw sqlite_error(rc, path + ": cannot open: " + message);
  }
  sqlite3_extended_result_codes(db_, 1);
}

Database::~Database() {
  sqlite3_close(db_);
}

void Database::exec(std::string_view sql) {
  char* error = nullptr;
  const std::string statement(sql);
  const int rc = sqlite3_exec(db_, statement.c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    std::string message = describe(db_, rc);
    sqlite3_free(error);
    throw sqlite_error(rc, message + " (in: " + statement.substr(0, 120) + ")");
  }
}

Statement Database::prepare(std::string_view sql) {
  return Statement(db_, sql);
}

Statement::Statement(sqlite3* db, std::string_view sql) : db_(db) {
  const int rc = sqlite3_prepare_v3(db, sql.data(), static_cast<int>(sql.size()),
                                    SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr);
  if (rc != SQLITE_OK) {
    throw sqlite_error(
        rc, std::string(sqlite3_errmsg(db)) + " (in: " + std::string(sql.substr(0, 120)) + ")");
  }
}

namespace {
void check_bind(sqlite3* db, int rc) {
  if (rc != SQLITE_OK) throw sqlite_error(rc, std::string("bind: ") + sqlite3_errmsg(db));
}
}  // namespace

void Statement::bind(int index, std::int64_t value) {
  check_bind(db_, sqlite3_bind_int64(stmt_, index, value));
}
void Statement::bind(int index, double value) {
  check_bind(db_, sqlite3_bind_double(stmt_, index, value));
}
void Statement::bind(int index, std::string_view text) {
  check_bind(db_, sqlite3_bind_text(stmt_, index, text.data(), static_cast<int>(text.size()),
                                    SQLITE_TRANSIENT));
}
void Statement::bind(int index, std::span<const std::uint8_t> blob) {
  check_bind(db_, sqlite3_bind_blob(stmt_, index, blob.data(), static_cast<int>(blob.size()),
                                    SQLITE_TRANSIENT));
}
void Statement::bind_null(int index) {
  check_bind(db_, sqlite3_bind_null(stmt_, index));
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  throw sqlite_error(rc, describe(db_, rc));
}

void Statement::run() {
  while (step()) {
  }
  reset();
}

std::string Statement::column_text(int i) const {
  const auto* text = sqlite3_column_text(stmt_, i);
  return text ? std::string(reinterpret_cast<const char*>(text),
                            static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i)))
              : std::string();
}

std::span<const std::uint8_t> Statement::column_blob(int i) const {
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, i));
  return {data, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i))};
}

}  // namespace roadcross::sqlite
