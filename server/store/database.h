#pragma once
// The one owner of catalogue.sqlite: a single connection behind a mutex, configured once (WAL,
// synchronous=FULL, foreign keys, busy timeout) and migrated to the current schema when opened.
// The catalogues share it, so every table lives under one schema version and one lock.

#include <filesystem>
#include <memory>
#include <mutex>

#include "vscan/common/status.h"

struct sqlite3;

namespace vscan::store {

class Database {
 public:
  ~Database();
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;

  // Opens or creates the file (and its directory); FAILED_PRECONDITION when its schema is newer
  // than this code.
  static StatusOr<std::shared_ptr<Database>> Open(const std::filesystem::path& path);

  // Guards the connection: hold it for every use of handle().
  std::mutex& mutex() { return mutex_; }
  sqlite3* handle() const { return db_; }

 private:
  explicit Database(sqlite3* db) : db_(db) {}
  std::mutex mutex_;
  sqlite3* db_;
};

}  // namespace vscan::store
