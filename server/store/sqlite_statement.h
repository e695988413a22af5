#pragma once
// Thin RAII helpers over the SQLite C API: prepared statements with bound parameters,
// error mapping to Status, and transactions that roll back on any failure.

#include <sqlite3.h>

#include <cerrno>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>

#include "vscan/common/status.h"

namespace vscan::store::sqlite {

// A full disk is RESOURCE_EXHAUSTED (free space, then retry); busy and I/O trouble is
// UNAVAILABLE (retry later); corruption is DATA_LOSS.
inline Status Error(sqlite3* db, int rc, std::string_view what) {
  std::string message = "catalogue: " + std::string(what) + ": " +
                        (db != nullptr ? sqlite3_errmsg(db) : sqlite3_errstr(rc));
  // Some writes report a full disk as an I/O error; the OS's errno tells.
  const int err = db != nullptr ? sqlite3_system_errno(db) : 0;
  if ((rc & 0xff) == SQLITE_IOERR && (err == ENOSPC || err == EDQUOT)) rc = SQLITE_FULL;
  switch (rc & 0xff) {
    case SQLITE_FULL:
      return ResourceExhausted(std::move(message) + " (no space left)");
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
    case SQLITE_IOERR:
    case SQLITE_CANTOPEN:
    case SQLITE_READONLY:
    case SQLITE_PERM:
    case SQLITE_NOMEM:
    case SQLITE_PROTOCOL:
      return Unavailable(std::move(message));
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      return DataLoss(std::move(message));
    default:
      return Internal(std::move(message));
  }
}

class Statement {
 public:
  static StatusOr<Statement> Prepare(sqlite3* db, std::string_view sql) {
    sqlite3_stmt* stmt = nullptr;
    int rc = sqlite3_prepare_v2(db, sql.data(), static_cast<int>(sql.size()), &stmt, nullptr);
    if (rc != SQLITE_OK) return Error(db, rc, "prepare");
    return Statement(db, stmt);
  }

  Statement(Statement&& other) noexcept
      : db_(other.db_), stmt_(std::exchange(other.stmt_, nullptr)), bind_rc_(other.bind_rc_) {}
  Statement& operator=(Statement&&) = delete;
  Statement(const Statement&) = delete;
  ~Statement() { sqlite3_finalize(stmt_); }

  // Parameters are numbered from 1; a failed bind is reported by the next Step().
  Statement& Bind(int index, int64_t value) { return Check(sqlite3_bind_int64(stmt_, index, value)); }
  Statement& Bind(int index, double value) { return Check(sqlite3_bind_double(stmt_, index, value)); }
  Statement& Bind(int index, std::string_view text) {
    return Check(sqlite3_bind_text64(stmt_, index, text.data(), text.size(), SQLITE_TRANSIENT, SQLITE_UTF8));
  }
  Statement& BindBlob(int index, std::string_view bytes) {
    return Check(sqlite3_bind_blob64(stmt_, index, bytes.data(), bytes.size(), SQLITE_TRANSIENT));
  }
  Statement& BindNull(int index) { return Check(sqlite3_bind_null(stmt_, index)); }

  // True when a row is ready, false when the statement has finished.
  StatusOr<bool> Step() {
    if (bind_rc_ != SQLITE_OK) return Error(db_, bind_rc_, "bind");
    int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    return Error(db_, rc, "step");
  }
  // Steps to completion, ignoring any rows.
  Status Run() {
    for (;;) {
      ASSIGN_OR_RETURN(bool row, Step());
      if (!row) return Status::Ok();
    }
  }

  bool IsNull(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }
  int64_t Int(int column) const { return sqlite3_column_int64(stmt_, column); }
  double Double(int column) const { return sqlite3_column_double(stmt_, column); }
  std::string Text(int column) const {
    const auto* text = sqlite3_column_text(stmt_, column);
    return text == nullptr ? std::string()
                           : std::string(reinterpret_cast<const char*>(text),
                                         static_cast<size_t>(sqlite3_column_bytes(stmt_, column)));
  }
  std::string_view Blob(int column) const {
    const void* data = sqlite3_column_blob(stmt_, column);
    return data == nullptr ? std::string_view()
                           : std::string_view(static_cast<const char*>(data),
                                              static_cast<size_t>(sqlite3_column_bytes(stmt_, column)));
  }

 private:
  Statement(sqlite3* db, sqlite3_stmt* stmt) : db_(db), stmt_(stmt) {}
  Statement& Check(int rc) {
    if (rc != SQLITE_OK && bind_rc_ == SQLITE_OK) bind_rc_ = rc;
    return *this;
  }

  sqlite3* db_;
  sqlite3_stmt* stmt_;
  int bind_rc_ = SQLITE_OK;
};

// Runs a fixed statement that takes no parameters.
inline Status Exec(sqlite3* db, std::string_view sql) {
  ASSIGN_OR_RETURN(Statement stmt, Statement::Prepare(db, sql));
  return stmt.Run();
}

// Runs body between BEGIN IMMEDIATE (or DEFERRED for reads) and COMMIT; any failure rolls back.
template <typename Body>
Status InTransaction(sqlite3* db, bool write, Body&& body) {
  RETURN_IF_ERROR(Exec(db, write ? "BEGIN IMMEDIATE" : "BEGIN DEFERRED"));
  Status status = body();
  if (status.ok()) status = Exec(db, "COMMIT");
  if (!status.ok() && !sqlite3_get_autocommit(db)) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
  }
  return status;
}

}  // namespace vscan::store::sqlite
