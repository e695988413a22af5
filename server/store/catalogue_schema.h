#pragma once
// The catalogue's schema and its migrations. PRAGMA user_version records the version a database
// is at; opening it runs the missing migrations in one transaction.

#include <array>
#include <string>
#include <string_view>

#include "store/sqlite_statement.h"

namespace vscan::store {

constexpr int kSchemaVersion = 1;

// kMigrations[i] upgrades a database from schema version i to i + 1.
constexpr std::array<std::string_view, kSchemaVersion> kMigrations = {
    R"sql(
CREATE TABLE meshes (
  mesh_id TEXT PRIMARY KEY NOT NULL,
  name TEXT NOT NULL,
  sha256 TEXT NOT NULL,
  vertex_count INTEGER NOT NULL,
  triangle_count INTEGER NOT NULL,
  min_x REAL NOT NULL, min_y REAL NOT NULL, min_z REAL NOT NULL,
  max_x REAL NOT NULL, max_y REAL NOT NULL, max_z REAL NOT NULL,
  source_unit INTEGER NOT NULL,
  source_scale REAL NOT NULL,
  create_time_ms INTEGER NOT NULL
);
CREATE INDEX meshes_by_sha256 ON meshes(sha256);
CREATE TABLE scenes (
  scene_id TEXT PRIMARY KEY NOT NULL,
  name TEXT NOT NULL,
  revision INTEGER NOT NULL,
  next_instance_id INTEGER NOT NULL,
  table_enabled INTEGER NOT NULL,
  table_centre_x REAL NOT NULL, table_centre_y REAL NOT NULL, table_centre_z REAL NOT NULL,
  table_axis_x REAL NOT NULL, table_axis_y REAL NOT NULL, table_axis_z REAL NOT NULL,
  table_angle_deg REAL NOT NULL,
  create_time_ms INTEGER NOT NULL,
  update_time_ms INTEGER NOT NULL
);
CREATE TABLE objects (
  object_id TEXT PRIMARY KEY NOT NULL,
  scene_id TEXT NOT NULL REFERENCES scenes(scene_id) ON DELETE CASCADE,
  mesh_id TEXT NOT NULL REFERENCES meshes(mesh_id),
  label TEXT NOT NULL,
  pose BLOB NOT NULL CHECK (length(pose) = 128),
  scale REAL NOT NULL,
  on_table INTEGER NOT NULL,
  instance_id INTEGER NOT NULL,
  UNIQUE (scene_id, instance_id)
);
CREATE INDEX objects_by_mesh ON objects(mesh_id);
)sql",
};

// Brings the database up to kSchemaVersion; FAILED_PRECONDITION when it is newer than this code.
inline Status MigrateSchema(sqlite3* db) {
  return sqlite::InTransaction(db, true, [&]() -> Status {
    ASSIGN_OR_RETURN(sqlite::Statement read, sqlite::Statement::Prepare(db, "PRAGMA user_version"));
    ASSIGN_OR_RETURN(bool row, read.Step());
    int version = row ? static_cast<int>(read.Int(0)) : 0;
    if (version > kSchemaVersion) {
      return FailedPrecondition("catalogue: database schema version " + std::to_string(version) +
                                " is newer than this server supports (" + std::to_string(kSchemaVersion) + ")");
    }
    for (int v = version; v < kSchemaVersion; ++v) {
      std::string_view script = kMigrations[static_cast<size_t>(v)];
      while (!script.empty()) {
        sqlite3_stmt* stmt = nullptr;
        const char* tail = nullptr;
        int rc = sqlite3_prepare_v2(db, script.data(), static_cast<int>(script.size()), &stmt, &tail);
        if (rc != SQLITE_OK) return sqlite::Error(db, rc, "migrate schema");
        script.remove_prefix(static_cast<size_t>(tail - script.data()));
        if (stmt == nullptr) continue;  // trailing whitespace
        rc = sqlite3_step(stmt);
        sqlite3_finalize(stmt);
        if (rc != SQLITE_DONE) return sqlite::Error(db, rc, "migrate schema");
      }
    }
    // A pragma takes no bound parameters; the value is our own constant.
    return sqlite::Exec(db, "PRAGMA user_version = " + std::to_string(kSchemaVersion));
  });
}

}  // namespace vscan::store
