// RobotCatalogue: mounts of robots in scenes.

#include <algorithm>
#include <cmath>

#include "store/robot_catalogue.h"
#include "store/robot_records.h"
#include "store/sqlite_statement.h"

namespace vscan::store {
namespace {

using sqlite::Statement;
namespace rows = robot_rows;

constexpr std::string_view kMountColumns =
    "mount_id, scene_id, robot_id, base_pose, tool_offset, links_visible, encoder_sigma, create_time_ms";

std::string SelectMounts(std::string_view where) {
  std::string sql = "SELECT ";
  sql.append(kMountColumns).append(" FROM mounts ").append(where);
  return sql;
}

StatusOr<MountRecord> ReadMount(const Statement& s) {
  MountRecord m;
  m.mount_id = s.Text(0);
  m.scene_id = s.Text(1);
  m.robot_id = s.Text(2);
  ASSIGN_OR_RETURN(m.base_pose, rows::DecodePose(s.Blob(3), "mounts.base_pose"));
  if (!s.Blob(4).empty()) {
    ASSIGN_OR_RETURN(m.tool_offset, rows::DecodePose(s.Blob(4), "mounts.tool_offset"));
  }
  m.links_visible = s.Int(5) != 0;
  ASSIGN_OR_RETURN(m.encoder_sigma, rows::DecodeDoubles(s.Blob(6), "mounts.encoder_sigma"));
  m.create_time_ms = s.Int(7);
  return m;
}

Status CheckMount(const MountRecord& m) {
  if (!m.base_pose.allFinite()) return InvalidArgument("base_pose: every element must be finite");
  if (m.tool_offset && !m.tool_offset->allFinite()) return InvalidArgument("tool_offset: every element must be finite");
  for (size_t i = 0; i < m.encoder_sigma.size(); ++i) {
    if (!(m.encoder_sigma[i] >= 0) || !std::isfinite(m.encoder_sigma[i])) {
      return InvalidArgument("encoder_sigma[" + std::to_string(i) + "]: must be finite and not negative");
    }
  }
  return Status::Ok();
}

}  // namespace

StatusOr<std::pair<MountRecord, uint64_t>> RobotCatalogue::InsertMount(MountRecord mount) {
  RETURN_IF_ERROR(CheckMount(mount));
  std::lock_guard lock(mutex_);
  mount.mount_id = rows::NewId("mnt_");
  mount.create_time_ms = rows::NowMs();
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(revision, rows::BumpSceneRevision(db_, mount.scene_id));
    ASSIGN_OR_RETURN(Statement robot, Statement::Prepare(db_, "SELECT 1 FROM robots WHERE robot_id = ?1"));
    robot.Bind(1, mount.robot_id);
    ASSIGN_OR_RETURN(bool found, robot.Step());
    if (!found) return rows::RobotNotFound(mount.robot_id);

    std::string sql = "INSERT INTO mounts (";
    sql.append(kMountColumns).append(") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)");
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, sql));
    s.Bind(1, mount.mount_id).Bind(2, mount.scene_id).Bind(3, mount.robot_id);
    s.BindBlob(4, rows::EncodePose(mount.base_pose));
    // Left unbound, parameter 5 is NULL: the robot's own tool offset.
    if (mount.tool_offset) s.BindBlob(5, rows::EncodePose(*mount.tool_offset));
    s.Bind(6, int64_t{mount.links_visible}).BindBlob(7, rows::EncodeDoubles(mount.encoder_sigma));
    s.Bind(8, mount.create_time_ms);
    return s.Run();
  }));
  return std::make_pair(std::move(mount), revision);
}

StatusOr<MountRecord> RobotCatalogue::GetMount(const std::string& mount_id) {
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, SelectMounts("WHERE mount_id = ?1")));
  s.Bind(1, mount_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return rows::MountNotFound(mount_id);
  return ReadMount(s);
}

StatusOr<std::vector<MountRecord>> RobotCatalogue::ListMounts(const std::string& scene_id, const std::string& after_id,
                                                              int limit) {
  if (limit <= 0) return InvalidArgument("limit: must be positive, got " + std::to_string(limit));
  std::lock_guard lock(mutex_);
  std::vector<MountRecord> mounts;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, false, [&]() -> Status {
    if (!scene_id.empty()) {
      ASSIGN_OR_RETURN(Statement scene, Statement::Prepare(db_, "SELECT 1 FROM scenes WHERE scene_id = ?1"));
      scene.Bind(1, scene_id);
      ASSIGN_OR_RETURN(bool found, scene.Step());
      if (!found) return rows::SceneNotFound(scene_id);
    }
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, SelectMounts("WHERE (?1 = '' OR scene_id = ?1) AND "
                                                                       "mount_id > ?2 ORDER BY mount_id LIMIT ?3")));
    s.Bind(1, scene_id).Bind(2, after_id).Bind(3, int64_t{std::min(limit, 1000)});
    for (;;) {
      ASSIGN_OR_RETURN(bool row, s.Step());
      if (!row) return Status::Ok();
      ASSIGN_OR_RETURN(MountRecord mount, ReadMount(s));
      mounts.push_back(std::move(mount));
    }
  }));
  return mounts;
}

StatusOr<uint64_t> RobotCatalogue::DeleteMount(const std::string& mount_id) {
  std::lock_guard lock(mutex_);
  uint64_t revision = 0;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement del,
                     Statement::Prepare(db_, "DELETE FROM mounts WHERE mount_id = ?1 RETURNING scene_id"));
    del.Bind(1, mount_id);
    ASSIGN_OR_RETURN(bool row, del.Step());
    if (!row) return rows::MountNotFound(mount_id);
    const std::string scene_id = del.Text(0);
    RETURN_IF_ERROR(del.Run());
    ASSIGN_OR_RETURN(revision, rows::BumpSceneRevision(db_, scene_id));
    return Status::Ok();
  }));
  return revision;
}

}  // namespace vscan::store
