#include "store/database.h"

#include <system_error>

#include "store/catalogue_schema.h"
#include "store/sqlite_statement.h"

namespace vscan::store {
namespace {

constexpr int kBusyTimeoutMs = 5000;

Status Configure(sqlite3* db) {
  int rc = sqlite3_busy_timeout(db, kBusyTimeoutMs);
  if (rc != SQLITE_OK) return sqlite::Error(db, rc, "busy_timeout");
  {
    // Finalized before any transaction: a live statement would block its COMMIT.
    ASSIGN_OR_RETURN(sqlite::Statement wal, sqlite::Statement::Prepare(db, "PRAGMA journal_mode = WAL"));
    ASSIGN_OR_RETURN(bool row, wal.Step());
    if (!row || wal.Text(0) != "wal") return Unavailable("catalogue: the database cannot use WAL journaling");
  }
  // The -wal and -shm files stay when the last connection closes, so that a restart on a full disk
  // needs no new space to open the catalogue and read it.
  int persist_wal = 1;
  rc = sqlite3_file_control(db, "main", SQLITE_FCNTL_PERSIST_WAL, &persist_wal);
  if (rc != SQLITE_OK) return sqlite::Error(db, rc, "persist WAL");
  RETURN_IF_ERROR(sqlite::Exec(db, "PRAGMA synchronous = FULL"));
  return sqlite::Exec(db, "PRAGMA foreign_keys = ON");
}

}  // namespace

Database::~Database() { sqlite3_close_v2(db_); }

StatusOr<std::shared_ptr<Database>> Database::Open(const std::filesystem::path& path) {
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) return Unavailable("catalogue: cannot create '" + path.parent_path().string() + "': " + ec.message());
  }
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX,
                                 nullptr);
  // The object owns the handle from here on, so every early return closes it.
  std::shared_ptr<Database> database(new Database(db));
  if (rc != SQLITE_OK) return sqlite::Error(db, rc, "open '" + path.string() + "'");
  RETURN_IF_ERROR(Configure(db));
  RETURN_IF_ERROR(MigrateSchema(db));
  return database;
}

}  // namespace vscan::store
