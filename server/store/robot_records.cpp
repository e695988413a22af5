#include "store/robot_records.h"



#include "store/byte_codec.h"
#include "store/sqlite_statement.h"

namespace vscan::store::robot_rows {
namespace {

constexpr uint32_t kMaxJoints = 1024;
constexpr uint32_t kMaxStrings = 1u << 20;

}  // namespace

std::string EncodePose(const Eigen::Matrix4d& pose) {
  ByteWriter out;
  for (int i = 0; i < 16; ++i) out.F64(pose.data()[i]);
  return out.Take();
}

StatusOr<Eigen::Matrix4d> DecodePose(std::string_view bytes, std::string_view column) {
  if (bytes.size() != 128) {
    return DataLoss("robot catalogue: stored " + std::string(column) + " has " + std::to_string(bytes.size()) +
                    " bytes, not 128");
  }
  ByteReader in(bytes, std::string(column));
  Eigen::Matrix4d pose;
  for (int i = 0; i < 16; ++i) {
    ASSIGN_OR_RETURN(pose.data()[i], in.F64());
  }
  return pose;
}

std::string EncodeJoints(const std::vector<JointRecord>& joints) {
  ByteWriter out;
  out.U32(static_cast<uint32_t>(joints.size()));
  for (const JointRecord& j : joints) {
    out.Bytes(j.name);
    out.U32(static_cast<uint32_t>(StoredCode(kJointKindCodes, j.type)));
    out.F64(j.lower);
    out.F64(j.upper);
    out.F64(j.max_velocity);
  }
  return out.Take();
}

StatusOr<std::vector<JointRecord>> DecodeJoints(std::string_view bytes) {
  ByteReader in(bytes, "robot catalogue: stored joints");
  ASSIGN_OR_RETURN(uint32_t count, in.U32());
  if (count > kMaxJoints) return in.Short();
  std::vector<JointRecord> joints(count);
  for (JointRecord& j : joints) {
    ASSIGN_OR_RETURN(std::string_view name, in.Bytes());
    j.name = name;
    ASSIGN_OR_RETURN(uint32_t type, in.U32());
    ASSIGN_OR_RETURN(j.type, FromStoredCode(kJointKindCodes, type, "robots.joints type of '" + j.name + "'"));
    ASSIGN_OR_RETURN(j.lower, in.F64());
    ASSIGN_OR_RETURN(j.upper, in.F64());
    ASSIGN_OR_RETURN(j.max_velocity, in.F64());
  }
  if (!in.done()) return in.Short();
  return joints;
}

std::string EncodeStrings(const std::vector<std::string>& strings) {
  ByteWriter out;
  out.U32(static_cast<uint32_t>(strings.size()));
  for (const std::string& s : strings) out.Bytes(s);
  return out.Take();
}

StatusOr<std::vector<std::string>> DecodeStrings(std::string_view bytes, std::string_view column) {
  ByteReader in(bytes, "robot catalogue: stored " + std::string(column));
  ASSIGN_OR_RETURN(uint32_t count, in.U32());
  if (count > kMaxStrings) return in.Short();
  std::vector<std::string> strings;
  for (uint32_t i = 0; i < count; ++i) {
    ASSIGN_OR_RETURN(std::string_view s, in.Bytes());
    strings.emplace_back(s);
  }
  if (!in.done()) return in.Short();
  return strings;
}

std::string EncodeDoubles(const std::vector<double>& values) {
  ByteWriter out;
  for (double v : values) out.F64(v);
  return out.Take();
}

StatusOr<std::vector<double>> DecodeDoubles(std::string_view bytes, std::string_view column) {
  if (bytes.size() % 8 != 0) {
    return DataLoss("robot catalogue: stored " + std::string(column) + " has " + std::to_string(bytes.size()) +
                    " bytes, not a multiple of 8");
  }
  ByteReader in(bytes, std::string(column));
  std::vector<double> values(bytes.size() / 8);
  for (double& v : values) {
    ASSIGN_OR_RETURN(v, in.F64());
  }
  return values;
}

Status SceneNotFound(const std::string& scene_id) { return NotFound("scene_id", "no scene '" + scene_id + "'"); }
Status RobotNotFound(const std::string& robot_id) { return NotFound("robot_id", "no robot '" + robot_id + "'"); }
Status MountNotFound(const std::string& mount_id) { return NotFound("mount_id", "no mount '" + mount_id + "'"); }

StatusOr<uint64_t> BumpSceneRevision(sqlite3* db, const std::string& scene_id) {
  ASSIGN_OR_RETURN(sqlite::Statement s,
                   sqlite::Statement::Prepare(db,
                                              "UPDATE scenes SET revision = revision + 1, update_time_ms = ?1 "
                                              "WHERE scene_id = ?2 RETURNING revision"));
  s.Bind(1, NowMs()).Bind(2, scene_id);
  ASSIGN_OR_RETURN(bool row, s.Step());
  if (!row) return SceneNotFound(scene_id);
  const auto revision = static_cast<uint64_t>(s.Int(0));
  RETURN_IF_ERROR(s.Run());
  return revision;
}

}  // namespace vscan::store::robot_rows
