#include "store/blob_gc.h"

#include <mutex>
#include <system_error>

#include "store/catalogue_schema.h"
#include "store/sqlite_statement.h"

namespace vscan::store {
namespace {

// One query over every blob column: true when some row names sha256.
std::string ReferencedSql() {
  std::string sql = "SELECT ";
  for (size_t i = 0; i < std::size(kBlobColumns); ++i) {
    if (i > 0) sql += " OR ";
    sql.append("EXISTS (SELECT 1 FROM ").append(kBlobColumns[i].table).append(" WHERE ");
    sql.append(kBlobColumns[i].column).append(" = ?1)");
  }
  return sql;
}

// Needs the database's lock.
StatusOr<bool> Referenced(sqlite3* db, const std::string& sha256) {
  ASSIGN_OR_RETURN(sqlite::Statement s, sqlite::Statement::Prepare(db, ReferencedSql()));
  s.Bind(1, sha256);
  ASSIGN_OR_RETURN(bool row, s.Step());
  return !row || s.Int(0) != 0;
}

bool OlderThan(const std::filesystem::directory_entry& entry, std::chrono::seconds min_age) {
  std::error_code ec;
  const auto mtime = entry.last_write_time(ec);
  return !ec && std::filesystem::file_time_type::clock::now() - mtime >= min_age;
}

}  // namespace

StatusOr<CollectedBlobs> CollectBlobs(Database& database, BlobStore& blobs, const std::vector<std::string>& candidates) {
  CollectedBlobs collected;
  std::lock_guard lock(database.mutex());
  for (const std::string& sha256 : candidates) {
    ASSIGN_OR_RETURN(const bool referenced, Referenced(database.handle(), sha256));
    if (referenced) continue;
    ASSIGN_OR_RETURN(const uint64_t bytes, blobs.RemoveUnpinned(sha256));
    if (bytes > 0) {
      ++collected.files;
      collected.bytes += bytes;
    }
  }
  return collected;
}

StatusOr<CollectedBlobs> SweepOrphanBlobs(Database& database, BlobStore& blobs, std::chrono::seconds min_age) {
  CollectedBlobs collected;
  std::error_code ec;
  std::filesystem::directory_iterator shards(blobs.root(), ec);
  if (ec) return Unavailable("blob store: cannot list '" + blobs.root().string() + "': " + ec.message());
  for (const auto& shard : shards) {
    if (!shard.is_directory(ec)) continue;
    std::vector<std::string> orphans;
    for (const auto& entry : std::filesystem::directory_iterator(shard.path(), ec)) {
      if (!entry.is_regular_file(ec) || !OlderThan(entry, min_age)) continue;
      const std::string name = entry.path().filename().string();
      if (IsBlobName(name)) {
        orphans.push_back(name);
      } else if (name.starts_with(".") && name.find(".tmp.") != std::string::npos) {
        // A write that never reached its rename.
        std::error_code size_ec;
        const uint64_t size = entry.file_size(size_ec);
        if (std::filesystem::remove(entry.path(), ec)) {
          ++collected.files;
          collected.bytes += size_ec ? 0 : size;
        }
      }
    }
    ASSIGN_OR_RETURN(const CollectedBlobs removed, CollectBlobs(database, blobs, orphans));
    collected.files += removed.files;
    collected.bytes += removed.bytes;
  }
  return collected;
}

}  // namespace vscan::store
