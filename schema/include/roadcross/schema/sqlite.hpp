// Thin RAII wrappers over the SQLite C API, shared by the writer and the runtime. Errors throw
// sqlite_error; the runtime catches them at its noexcept API boundary. Include only from .cpp
// files: the runtime's public header must not pull in <sqlite3.h>.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace roadcross::sqlite {

class sqlite_error : public std::runtime_error {
 public:
  sqlite_error(int code, const std::string& what) : std::runtime_error(what), code_(code) {}
  int code() const noexcept { return code_; }

 private:
  int code_;
};

class Statement;

class Database {
 public:
  /// Opens `path` with SQLITE_OPEN_* `flags` through the VFS named `vfs` (nullptr: SQLite's
  /// default); throws sqlite_error naming the path.
  Database(const std::string& path, int flags, const char* vfs = nullptr);
  Database(Database&& other) noexcept : db_(other.db_) { other.db_ = nullptr; }
  Database& operator=(Database&&) = delete;
  Database(const Database&) = delete;
  ~Database();

  void exec(std::string_view sql);
  Statement prepare(std::string_view sql);
  sqlite3* handle() const noexcept { return db_; }
  std::string last_error() const { return sqlite3_errmsg(db_); }

 private:
  sqlite3* db_ = nullptr;
};

class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);
  Statement(Statement&& other) noexcept : db_(other.db_), stmt_(other.stmt_) {
    other.stmt_ = nullptr;
  }
  Statement& operator=(Statement&&) = delete;
  Statement(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  // Parameters are 1-based as in SQLite.
  void bind(int index, std::int64_t value);
  void bind(int index, int value) { bind(index, static_cast<std::int64_t>(value)); }
  void bind(int index, double value);
  void bind(int index, std::string_view text);
  void bind(int index, std::span<const std::uint8_t> blob);
  void bind_null(int index);
  template <typename T>
  void bind(int index, const std::optional<T>& value) {
    if (value) {
      bind(index, *value);
    } else {
      bind_null(index);
    }
  }

  /// Steps once: true while a row is available, false when done.
  bool step();
  /// Steps a statement that returns no rows, then resets it for reuse.
  void run();
  void reset() noexcept {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }

  int parameter_count() const noexcept { return sqlite3_bind_parameter_count(stmt_); }
  /// The raw statement, for reading a column whatever its type (sqlite3_column_type).
  sqlite3_stmt* handle() const noexcept { return stmt_; }

  std::int64_t column_int64(int i) const { return sqlite3_column_int64(stmt_, i); }
  double column_double(int i) const { return sqlite3_column_double(stmt_, i); }
  bool column_is_null(int i) const { return sqlite3_column_type(stmt_, i) == SQLITE_NULL; }
  /// SQLITE_INTEGER, SQLITE_FLOAT, SQLITE_TEXT, SQLITE_BLOB or SQLITE_NULL.
  int column_type(int i) const { return sqlite3_column_type(stmt_, i); }
  std::string column_text(int i) const;
  /// The text of column `i` without a copy: valid until the next step() or reset().
  std::string_view column_text_view(int i) const {
    const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, i));
    return text ? std::string_view(text, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i)))
                : std::string_view();
  }
  std::span<const std::uint8_t> column_blob(int i) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

}  // namespace roadcross::sqlite
