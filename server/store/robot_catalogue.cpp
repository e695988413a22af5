#include "store/robot_catalogue.h"

#include <algorithm>
#include <utility>

#include "store/robot_records.h"
#include "store/sqlite_statement.h"

namespace vscan::store {
namespace {

using sqlite::Statement;
namespace rows = robot_rows;

constexpr std::string_view kRobotColumns =
    "robot_id, name, urdf_path, base_link, tip_link, tool_offset, bundle_sha256, bundle_bytes, file_count, dof, "
    "joints, reach, warnings, create_time_ms";

std::string SelectRobots(std::string_view where) {
  std::string sql = "SELECT ";
  sql.append(kRobotColumns).append(" FROM robots ").append(where);
  return sql;
}

StatusOr<RobotRecord> ReadRobot(const Statement& s) {
  RobotRecord r;
  r.robot_id = s.Text(0);
  r.name = s.Text(1);
  r.urdf_path = s.Text(2);
  r.base_link = s.Text(3);
  r.tip_link = s.Text(4);
  ASSIGN_OR_RETURN(r.tool_offset, rows::DecodePose(s.Blob(5), "robots.tool_offset"));
  r.bundle_sha256 = s.Text(6);
  r.bundle_bytes = static_cast<uint64_t>(s.Int(7));
  r.file_count = static_cast<uint32_t>(s.Int(8));
  ASSIGN_OR_RETURN(r.joints, rows::DecodeJoints(s.Blob(10)));
  if (static_cast<int64_t>(r.joints.size()) != s.Int(9)) {
    return DataLoss("robot catalogue: robot '" + r.robot_id + "' lists " + std::to_string(r.joints.size()) +
                    " joints but records dof " + std::to_string(s.Int(9)));
  }
  r.reach = s.Double(11);
  ASSIGN_OR_RETURN(r.warnings, rows::DecodeStrings(s.Blob(12), "robots.warnings"));
  r.create_time_ms = s.Int(13);
  return r;
}

Status CheckRobot(const RobotRecord& r) {
  if (!r.tool_offset.allFinite()) return InvalidArgument("tool_offset: every element must be finite");
  if (r.joints.empty()) return InvalidArgument("joints: a robot needs at least one movable joint");
  if (r.bundle_sha256.size() != 64) return InvalidArgument("bundle_sha256: not a SHA-256 hex digest");
  return Status::Ok();
}

}  // namespace

RobotCatalogue::RobotCatalogue(std::shared_ptr<Database> database)
    : database_(std::move(database)), mutex_(database_->mutex()), db_(database_->handle()) {}

StatusOr<std::unique_ptr<RobotCatalogue>> RobotCatalogue::Open(const std::filesystem::path& db_path) {
  ASSIGN_OR_RETURN(std::shared_ptr<Database> database, Database::Open(db_path));
  return std::make_unique<RobotCatalogue>(std::move(database));
}

StatusOr<RobotRecord> RobotCatalogue::InsertRobot(RobotRecord robot) {
  RETURN_IF_ERROR(CheckRobot(robot));
  std::lock_guard lock(mutex_);
  robot.robot_id = rows::NewId("rbt_");
  robot.create_time_ms = rows::NowMs();
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    std::string sql = "INSERT INTO robots (";
    sql.append(kRobotColumns).append(") VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)");
    ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, sql));
    s.Bind(1, robot.robot_id).Bind(2, robot.name).Bind(3, robot.urdf_path).Bind(4, robot.base_link);
    s.Bind(5, robot.tip_link).BindBlob(6, rows::EncodePose(robot.tool_offset)).Bind(7, robot.bundle_sha256);
    s.Bind(8, static_cast<int64_t>(robot.bundle_bytes)).Bind(9, int64_t{robot.file_count});
    s.Bind(10, static_cast<int64_t>(robot.joints.size())).BindBlob(11, rows::EncodeJoints(robot.joints));
    s.Bind(12, robot.reach).BindBlob(13, rows::EncodeStrings(robot.warnings)).Bind(14, robot.create_time_ms);
    return s.Run();
  }));
  return robot;
}

StatusOr<RobotRecord> RobotCatalogue::GetRobot(const std::string& robot_id) {
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s, Statement::Prepare(db_, SelectRobots("WHERE robot_id = ?1")));
  s.Bind(1, robot_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return rows::RobotNotFound(robot_id);
  return ReadRobot(s);
}

StatusOr<std::vector<RobotRecord>> RobotCatalogue::ListRobots(const std::string& after_id, int limit) {
  if (limit <= 0) return InvalidArgument("limit: must be positive, got " + std::to_string(limit));
  std::lock_guard lock(mutex_);
  ASSIGN_OR_RETURN(Statement s,
                   Statement::Prepare(db_, SelectRobots("WHERE robot_id > ?1 ORDER BY robot_id LIMIT ?2")));
  s.Bind(1, after_id).Bind(2, int64_t{std::min(limit, 1000)});
  std::vector<RobotRecord> robots;
  for (;;) {
    ASSIGN_OR_RETURN(bool row, s.Step());
    if (!row) return robots;
    ASSIGN_OR_RETURN(RobotRecord robot, ReadRobot(s));
    robots.push_back(std::move(robot));
  }
}

StatusOr<std::pair<std::string, bool>> RobotCatalogue::DeleteRobot(const std::string& robot_id) {
  std::lock_guard lock(mutex_);
  std::pair<std::string, bool> result;
  RETURN_IF_ERROR(sqlite::InTransaction(db_, true, [&]() -> Status {
    ASSIGN_OR_RETURN(Statement find, Statement::Prepare(db_, "SELECT bundle_sha256 FROM robots WHERE robot_id = ?1"));
    find.Bind(1, robot_id);
    ASSIGN_OR_RETURN(bool found, find.Step());
    if (!found) return rows::RobotNotFound(robot_id);
    result.first = find.Text(0);

    ASSIGN_OR_RETURN(Statement mounts, Statement::Prepare(db_,
                                                          "SELECT count(*), min(mount_id), min(scene_id) FROM mounts "
                                                          "WHERE robot_id = ?1"));
    mounts.Bind(1, robot_id);
    ASSIGN_OR_RETURN(bool counted, mounts.Step());
    if (const int64_t count = counted ? mounts.Int(0) : 0; count > 0) {
      return FailedPrecondition("robot_id: robot '" + robot_id + "' has " + std::to_string(count) +
                                (count == 1 ? " mount" : " mounts") + " (e.g. '" + mounts.Text(1) + "' in scene '" +
                                mounts.Text(2) + "'); unmount it first");
    }

    ASSIGN_OR_RETURN(Statement del, Statement::Prepare(db_, "DELETE FROM robots WHERE robot_id = ?1"));
    del.Bind(1, robot_id);
    RETURN_IF_ERROR(del.Run());

    ASSIGN_OR_RETURN(Statement shared, Statement::Prepare(db_, "SELECT count(*) FROM robots WHERE bundle_sha256 = ?1"));
    shared.Bind(1, result.first);
    ASSIGN_OR_RETURN(bool row, shared.Step());
    result.second = !row || shared.Int(0) == 0;
    return Status::Ok();
  }));
  return result;
}

}  // namespace vscan::store
