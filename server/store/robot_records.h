#pragma once
// Helpers of the robot catalogue: ids, clock, the byte encodings of pose, joint, warning and
// sigma columns, and the scene revision bump. Internal to store/.

#include <sqlite3.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "store/ids.h"
#include "store/robot_catalogue.h"
#include "vscan/common/status.h"

namespace vscan::store::robot_rows {

using store::NewId;
using store::NowMs;

// 16 little-endian doubles, column-major.
std::string EncodePose(const Eigen::Matrix4d& pose);
StatusOr<Eigen::Matrix4d> DecodePose(std::string_view bytes, std::string_view column);

std::string EncodeJoints(const std::vector<JointRecord>& joints);
StatusOr<std::vector<JointRecord>> DecodeJoints(std::string_view bytes);

std::string EncodeStrings(const std::vector<std::string>& strings);
StatusOr<std::vector<std::string>> DecodeStrings(std::string_view bytes, std::string_view column);

std::string EncodeDoubles(const std::vector<double>& values);
StatusOr<std::vector<double>> DecodeDoubles(std::string_view bytes, std::string_view column);

Status SceneNotFound(const std::string& scene_id);
Status RobotNotFound(const std::string& robot_id);
Status MountNotFound(const std::string& mount_id);

// Bumps the scene's revision and update time inside the caller's transaction.
StatusOr<uint64_t> BumpSceneRevision(sqlite3* db, const std::string& scene_id);

}  // namespace vscan::store::robot_rows
