#pragma once
// The catalogue's schema and its migrations. PRAGMA user_version records the version a database
// is at; opening it runs the missing migrations in one transaction.

#include <array>
#include <iterator>
#include <string>
#include <string_view>

#include "store/sqlite_statement.h"

namespace vscan::store {

// One step of the schema's history: it takes a database from version - 1 to version.
struct Migration {
  int version;
  std::string_view sql;
};

// Append only: a released step never changes, since databases out there have run it.
constexpr Migration kMigrations[] = {
    {1, R"sql(
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
)sql"},
    // Robots, mounts and jobs join the versioned schema. Version 1 servers created these tables
    // unversioned on every start, hence IF NOT EXISTS.
    {2, R"sql(
CREATE TABLE IF NOT EXISTS robots (
  robot_id TEXT PRIMARY KEY NOT NULL,
  name TEXT NOT NULL,
  urdf_path TEXT NOT NULL,
  base_link TEXT NOT NULL,
  tip_link TEXT NOT NULL,
  tool_offset BLOB NOT NULL CHECK (length(tool_offset) = 128),
  bundle_sha256 TEXT NOT NULL,
  bundle_bytes INTEGER NOT NULL,
  file_count INTEGER NOT NULL,
  dof INTEGER NOT NULL,
  joints BLOB NOT NULL,
  reach REAL NOT NULL,
  warnings BLOB NOT NULL,
  create_time_ms INTEGER NOT NULL
);
CREATE INDEX IF NOT EXISTS robots_by_sha256 ON robots(bundle_sha256);
CREATE TABLE IF NOT EXISTS mounts (
  mount_id TEXT PRIMARY KEY NOT NULL,
  scene_id TEXT NOT NULL REFERENCES scenes(scene_id) ON DELETE CASCADE,
  robot_id TEXT NOT NULL REFERENCES robots(robot_id),
  base_pose BLOB NOT NULL CHECK (length(base_pose) = 128),
  tool_offset BLOB CHECK (tool_offset IS NULL OR length(tool_offset) = 128),
  links_visible INTEGER NOT NULL,
  encoder_sigma BLOB NOT NULL,
  create_time_ms INTEGER NOT NULL
);
CREATE INDEX IF NOT EXISTS mounts_by_scene ON mounts(scene_id);
CREATE INDEX IF NOT EXISTS mounts_by_robot ON mounts(robot_id);
CREATE TABLE IF NOT EXISTS jobs (
  job_id TEXT PRIMARY KEY NOT NULL,
  kind TEXT NOT NULL,
  state INTEGER NOT NULL,
  name TEXT NOT NULL,
  spec BLOB NOT NULL,
  message TEXT NOT NULL,
  steps_done INTEGER NOT NULL,
  steps_total INTEGER NOT NULL,
  last_sequence INTEGER NOT NULL,
  create_time_ms INTEGER NOT NULL,
  update_time_ms INTEGER NOT NULL
);
CREATE INDEX IF NOT EXISTS jobs_by_state ON jobs(state);
CREATE TABLE IF NOT EXISTS job_artifacts (
  artifact_id TEXT PRIMARY KEY NOT NULL,
  job_id TEXT NOT NULL REFERENCES jobs(job_id) ON DELETE CASCADE,
  ordinal INTEGER NOT NULL,
  name TEXT NOT NULL,
  media_type TEXT NOT NULL,
  sha256 TEXT NOT NULL,
  size_bytes INTEGER NOT NULL,
  info BLOB NOT NULL,
  create_time_ms INTEGER NOT NULL,
  UNIQUE (job_id, ordinal)
);
CREATE INDEX IF NOT EXISTS job_artifacts_by_sha256 ON job_artifacts(sha256);
)sql"},
    // Retention finds ended jobs by the time of their last change.
    {3, "CREATE INDEX jobs_by_state_and_update_time ON jobs(state, update_time_ms);"},
    // Point clouds as resources: uploaded by clients, or the scans of a campaign (which go with
    // their job).
    {4, R"sql(
CREATE TABLE clouds (
  cloud_id TEXT PRIMARY KEY NOT NULL,
  name TEXT NOT NULL,
  sha256 TEXT NOT NULL,
  size_bytes INTEGER NOT NULL,
  points INTEGER NOT NULL,
  fields TEXT NOT NULL,
  origin INTEGER NOT NULL,
  job_id TEXT REFERENCES jobs(job_id) ON DELETE CASCADE,
  scene_id TEXT NOT NULL,
  sensor_pose BLOB CHECK (sensor_pose IS NULL OR length(sensor_pose) = 128),
  camera BLOB,
  table_angle_deg REAL,
  create_time_ms INTEGER NOT NULL
);
CREATE INDEX clouds_by_sha256 ON clouds(sha256);
CREATE INDEX clouds_by_job ON clouds(job_id);
)sql"},
    // The frame a cloud's points are in (1 world, 2 sensor): a sensor pose alone does not say
    // whether it still has to be applied.
    {5, "ALTER TABLE clouds ADD COLUMN frame INTEGER NOT NULL DEFAULT 1;"},
    // Materials: a mesh's default and an object's override, each a preset's name or four values
    // (store/material_columns.h); rows from before stay NULL, which reads as no material set.
    {6, R"sql(
ALTER TABLE meshes ADD COLUMN material_preset TEXT;
ALTER TABLE meshes ADD COLUMN material_albedo REAL;
ALTER TABLE meshes ADD COLUMN material_metallic REAL;
ALTER TABLE meshes ADD COLUMN material_roughness REAL;
ALTER TABLE meshes ADD COLUMN material_specular REAL;
ALTER TABLE objects ADD COLUMN material_preset TEXT;
ALTER TABLE objects ADD COLUMN material_albedo REAL;
ALTER TABLE objects ADD COLUMN material_metallic REAL;
ALTER TABLE objects ADD COLUMN material_roughness REAL;
ALTER TABLE objects ADD COLUMN material_specular REAL;
)sql"},
};

constexpr int kSchemaVersion = static_cast<int>(std::size(kMigrations));

constexpr bool MigrationsAreNumberedInOrder() {
  for (size_t i = 0; i < std::size(kMigrations); ++i) {
    if (kMigrations[i].version != static_cast<int>(i) + 1) return false;
  }
  return true;
}
static_assert(MigrationsAreNumberedInOrder(), "kMigrations must be numbered 1, 2, 3, ... in order");

// Every column that names a blob by its SHA-256: a blob file may go only when none of them does.
struct BlobColumn {
  std::string_view table;
  std::string_view column;
};
constexpr BlobColumn kBlobColumns[] = {
    {"meshes", "sha256"}, {"robots", "bundle_sha256"}, {"job_artifacts", "sha256"}, {"clouds", "sha256"}};

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
    for (const Migration& migration : kMigrations) {
      if (migration.version <= version) continue;
      std::string_view script = migration.sql;
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
    // Written only when it changes: an opening that writes nothing also opens on a full disk.
    if (version == kSchemaVersion) return Status::Ok();
    // A pragma takes no bound parameters; the value is our own constant.
    return sqlite::Exec(db, "PRAGMA user_version = " + std::to_string(kSchemaVersion));
  });
}

}  // namespace vscan::store
