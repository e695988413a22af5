#pragma once
// A catalogue as the previous release (schema version 1) left it: its CREATE statements verbatim
// (meshes, scenes and objects versioned; robots, mounts and jobs created unversioned by their own
// connections), with one row of each kind.

#include <string_view>

namespace vscan::store::testing {

constexpr std::string_view kCatalogueV1 = R"sql(
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
PRAGMA user_version = 1;
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

INSERT INTO meshes VALUES ('msh_00000000000000a1', 'bunny',
  'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa', 8146, 16301,
  -0.5, -0.25, 0.0, 0.5, 0.25, 0.75, 3, 0.001, 1700000000000);
INSERT INTO scenes VALUES ('scn_00000000000000b1', 'desk', 4, 2, 1, 0.0, 0.0, -0.1, 0.0, 0.0, 1.0,
  30.0, 1700000000001, 1700000000002);
INSERT INTO objects VALUES ('obj_00000000000000c1', 'scn_00000000000000b1', 'msh_00000000000000a1',
  'part', X'000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000d03f000000000000e0bf000000000000c03f000000000000f03f',
  1.5, 1, 1);
INSERT INTO robots VALUES ('rbt_00000000000000d1', 'arm', 'arm.urdf', 'base', 'tool',
  X'000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f',
  'bbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbbb', 4096, 3, 2,
  X'02000000080000000000000073686f756c6465720100000000000000000008c0000000000000084000000000000000000500000000000000736c696465030000000000000000000000000000000000e03f0000000000000000',
  0.85, X'0100000004000000000000007761726e', 1700000000003);
INSERT INTO mounts VALUES ('mnt_00000000000000e1', 'scn_00000000000000b1', 'rbt_00000000000000d1',
  X'000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000f03f0000000000000000000000000000d03f000000000000e0bf000000000000c03f000000000000f03f',
  NULL, 1, X'fca9f1d24d62503ffca9f1d24d62603f', 1700000000004);
INSERT INTO jobs VALUES ('job_00000000000000f1', 'campaign', 3, 'turntable', X'0a0373636e', 'done', 2, 2, 5,
  1700000000005, 1700000000006);
INSERT INTO jobs VALUES ('job_00000000000000f2', 'campaign', 6, '', X'', 'server stopped', 0, 4, 1,
  1700000000007, 1700000000008);
INSERT INTO job_artifacts VALUES ('art_0000000000000011', 'job_00000000000000f1', 0, 'scan-r00-v00.ply',
  'model/ply', 'cccccccccccccccccccccccccccccccccccccccccccccccccccccccccccccccc', 1234, X'0801', 1700000000009);
INSERT INTO job_artifacts VALUES ('art_0000000000000012', 'job_00000000000000f1', 1, 'campaign.json',
  'application/json', 'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa', 56, X'', 1700000000010);
)sql";

}  // namespace vscan::store::testing
